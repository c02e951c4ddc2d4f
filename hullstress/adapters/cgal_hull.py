"""CGAL's convex hulls through the ``cgal`` SWIG bindings (PyPI package ``cgal``).

===========================  ===  =================================================
name                         dim  CGAL function
===========================  ===  =================================================
cgal-convex-hull-3d          3    ``CGAL_Convex_hull_3.convex_hull_3`` into a ``Polyhedron_3``
cgal-convex-hull-2d          2    ``CGAL_Convex_hull_2.convex_hull_2`` (Akl-Toussaint)
cgal-graham-andrew-2d        2    ``CGAL_Convex_hull_2.ch_graham_andrew`` (monotone chain)
cgal-jarvis-2d               2    ``CGAL_Convex_hull_2.ch_jarvis`` (gift wrapping)
===========================  ===  =================================================

The bindings use CGAL's exact-predicates kernel, so these are correct
reference implementations: they belong in a sweep as positive controls next
to the in-house monotone chain and Jarvis march.

CGAL returns points, not indices.  Its kernel stores the input doubles
unchanged, so each returned point is mapped back to its input row by exact
coordinate match; rows with identical coordinates map to the lowest index
(see :mod:`hullstress.adapters._mapping`).

Orientation: CGAL's 2D functions return the extreme points counter-clockwise;
a ``Polyhedron_3`` facet's halfedge cycle is counter-clockwise seen from
outside.  The adapters return them in that order.

Degenerate input: for coplanar or collinear points ``convex_hull_3`` builds
an open surface (a triangulated polygon, or degenerate triangles), and for
fewer than three points none; the 2D functions return fewer than three points
for collinear input.  Those are CGAL's lower-dimensional answers, not closed
hulls, so the adapters raise ``ValueError`` saying what CGAL returned, and the
harness records ``rejected`` (or ``error`` on a full-dimensional input).

Declared contracts: CGAL documents ``convex_hull_2`` and its variants as
producing "the counterclockwise sequence of extreme points" and
``convex_hull_3`` as the polyhedron whose vertices are the extreme points
(a kept non-extreme vertex was accepted as a bug, CGAL issue 3192) with
triangular facets; the adapters raise on flat input.  So: ``strict,flat=raise``
in 2D and ``strict,faces=triangles,flat=raise`` in 3D (``docs/contracts.md``).

Non-finite input is passed through unchanged, as the library would get it:
with a NaN or infinite coordinate ``convex_hull_3`` kills the process with
SIGFPE (cgal 6.0.1, Python 3.11, Linux x86_64); the runner's worker isolation
records that as ``crash``.  Do not call this adapter in-process on such input.

Examples
--------
>>> import numpy as np
>>> cube = np.array([[x, y, z] for x in (0.0, 1.0) for y in (0.0, 1.0) for z in (0.0, 1.0)])
>>> cgal_convex_hull_3d(cube).shape
(12, 3)
>>> cgal_convex_hull_2d(np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.5, 0.2]])).tolist()
[0, 1, 2]
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

# Kernel and Polyhedron_3 first: SWIG registers a type's destructor with the
# first module that defines it, and importing the hull modules first makes
# SWIG print "memory leak ... no destructor found" for every returned object.
from CGAL.CGAL_Kernel import Point_2, Point_3  # isort: skip
from CGAL.CGAL_Polyhedron_3 import Polyhedron_3  # isort: skip
from CGAL import CGAL_Convex_hull_2, CGAL_Convex_hull_3  # isort: skip

from .._registry import register_algorithm
from ._mapping import coordinate_table, indices_of

__all__ = [
    "ALGORITHM_NAMES",
    "cgal_convex_hull_3d",
    "cgal_convex_hull_2d",
    "cgal_graham_andrew_2d",
    "cgal_jarvis_2d",
]

#: What the 2D adapters promise (see "Declared contracts" above).
CGAL_2D_CONTRACT = "strict,flat=raise"

#: The algorithm names this module registers.
ALGORITHM_NAMES: tuple[str, ...] = (
    "cgal-convex-hull-3d",
    "cgal-convex-hull-2d",
    "cgal-graham-andrew-2d",
    "cgal-jarvis-2d",
)


@register_algorithm("cgal-convex-hull-3d", dim=3, contract="strict,faces=triangles,flat=raise")
def cgal_convex_hull_3d(points: np.ndarray, /) -> np.ndarray | list[list[int]]:
    """CGAL convex_hull_3 (exact predicates) via the cgal bindings (3D).

    Parameters
    ----------
    points : ndarray of shape (n, 3), float64

    Returns
    -------
    ndarray of shape (m, 3), int64, or list of list of int
        Triangles counter-clockwise seen from outside (a list of polygons if
        CGAL ever returns a non-triangular facet).

    Raises
    ------
    ValueError
        When CGAL's result is not a closed surface (coplanar or collinear input,
        fewer than four distinct points).
    RuntimeError
        When a returned vertex is not an input point.
    """
    poly = Polyhedron_3()
    CGAL_Convex_hull_3.convex_hull_3([Point_3(x, y, z) for x, y, z in points.tolist()], poly)
    n_vertices, n_facets = poly.size_of_vertices(), poly.size_of_facets()
    if n_facets == 0:
        raise ValueError(
            f"CGAL returned no facets ({n_vertices} vertices), its answer for fewer than "
            "three distinct points, not a closed hull"
        )
    if not poly.is_closed():
        raise ValueError(
            f"CGAL returned an open surface ({n_vertices} vertices, {n_facets} facets), "
            "its answer for coplanar or collinear input, not a closed hull"
        )
    table = coordinate_table(points)
    faces: list[list[int]] = []
    for facet in poly.facets():
        h = facet.halfedge()
        coords = []
        for _ in range(facet.facet_degree()):
            p = h.vertex().point()
            coords.append((p.x(), p.y(), p.z()))
            h = h.next()
        faces.append(indices_of(coords, table, library="CGAL"))
    if all(len(f) == 3 for f in faces):
        return np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    return faces


def _hull_2d(points: np.ndarray, function: Callable[[list[Any], list[Any]], Any], name: str) -> np.ndarray:
    """Run one of CGAL's 2D hull functions and map its points back to indices."""
    result: list[Any] = []
    function([Point_2(x, y) for x, y in points.tolist()], result)
    if len(result) < 3:
        raise ValueError(
            f"CGAL {name} returned {len(result)} hull point(s), its answer for collinear "
            "input or fewer than three distinct points, not a polygon"
        )
    coords = [(p.x(), p.y()) for p in result]
    return np.asarray(indices_of(coords, coordinate_table(points), library="CGAL"), dtype=np.int64)


@register_algorithm("cgal-convex-hull-2d", dim=2, contract=CGAL_2D_CONTRACT)
def cgal_convex_hull_2d(points: np.ndarray, /) -> np.ndarray:
    """CGAL convex_hull_2 (Akl-Toussaint, exact predicates) via the cgal bindings (2D).

    Parameters
    ----------
    points : ndarray of shape (n, 2), float64

    Returns
    -------
    ndarray of shape (k,), int64
        Extreme points, counter-clockwise.

    Raises
    ------
    ValueError
        When CGAL returns fewer than three points (collinear input).
    """
    return _hull_2d(points, CGAL_Convex_hull_2.convex_hull_2, "convex_hull_2")


@register_algorithm("cgal-graham-andrew-2d", dim=2, contract=CGAL_2D_CONTRACT)
def cgal_graham_andrew_2d(points: np.ndarray, /) -> np.ndarray:
    """CGAL ch_graham_andrew (monotone chain, exact predicates) via the cgal bindings (2D).

    Same parameters, return value and errors as :func:`cgal_convex_hull_2d`.
    """
    return _hull_2d(points, CGAL_Convex_hull_2.ch_graham_andrew, "ch_graham_andrew")


@register_algorithm("cgal-jarvis-2d", dim=2, contract=CGAL_2D_CONTRACT)
def cgal_jarvis_2d(points: np.ndarray, /) -> np.ndarray:
    """CGAL ch_jarvis (gift wrapping, exact predicates) via the cgal bindings (2D).

    Same parameters, return value and errors as :func:`cgal_convex_hull_2d`.
    """
    return _hull_2d(points, CGAL_Convex_hull_2.ch_jarvis, "ch_jarvis")
