"""Why the sphere method loses a hull, measured exactly: vertex loss and face-structure change.

Kenwright's preprocessing (:mod:`hullstress.sphere`) hands the algorithm the
surface points projected onto a unit sphere, and the harness maps the
algorithm's hull back to input rows.  That mapped-back hull can fail to be the
input's hull for two separate reasons, and a sweep records each (columns of
:data:`SPHERE_CAUSE_COLUMNS`, one set per sphere=on row):

* **vertex loss** (``sphere_lost_extreme`` of ``sphere_extreme``): true
  extreme points of the input that the surface list does not hold (the
  support mapping never returned them, or duplicate removal merged them into
  a kept neighbour).  Counted against the case's certified extreme set
  (:attr:`hullstress.checker.qhull.QhullReference.extreme`), by coordinates,
  so duplicated rows count once.
* **face-structure change** (``sphere_kept_structure``): had the surface list
  held exactly the true extreme points, would the method still lose the
  hull?  Those points are projected from the method's centroid, their exact
  hull (Qhull's, certified by the exact checks against the projected points)
  is mapped back and judged as the input's hull by the exact checker.
  ``changed`` says that moving the vertices radially onto a sphere alone
  changes which of them span faces: the hull of the projection is not the
  hull of the points, whatever the support mapping keeps.

``sphere_structure`` is the same judgement on the projection the method
actually made (its surface list): ``changed`` whenever a vertex was lost,
and, with no vertex lost, exactly when the face structure changed; it is the
algorithm-independent twin of the ``sphere_method`` verdict.  A projection
of lower affine rank than the input is ``changed`` (its hull cannot map back
to the input's).

None of these depends on the algorithm, so they are computed once per (case,
projection) in a worker and repeated on the rows of every algorithm; a row
whose call timed out or crashed has none.  A structure is judged on one
certified hull of the projected points: when several projected points are
exactly coplanar its triangulation is one of several, which random clouds
never hit.
"""

from __future__ import annotations

from collections import OrderedDict
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from .records import SphereStructure

__all__ = ["SphereCauses", "SPHERE_CAUSE_COLUMNS", "sphere_causes", "lost_extreme", "empty_sphere_causes"]

#: Columns of the results table that carry :class:`SphereCauses` (empty with sphere off).
SPHERE_CAUSE_COLUMNS = ("sphere_extreme", "sphere_lost_extreme", "sphere_structure", "sphere_kept_structure")


@dataclass(frozen=True)
class SphereCauses:
    """The two causes of a sphere-method failure, measured on one projection.

    Attributes
    ----------
    extreme : int or None
        Distinct extreme points of the input (None when no certified extreme set exists).
    lost_extreme : int or None
        How many of them the surface list dropped (None when ``extreme`` is None).
    structure : SphereStructure
        Whether the exact hull of the method's projected points, mapped back, is the input's hull.
    kept_structure : SphereStructure
        The same for the projection of exactly the true extreme points (every vertex kept).
    """

    extreme: int | None
    lost_extreme: int | None
    structure: SphereStructure
    kept_structure: SphereStructure

    def columns(self) -> dict[str, Any]:
        """The causes as table columns, in :data:`SPHERE_CAUSE_COLUMNS` order."""
        return {"sphere_extreme": self.extreme, "sphere_lost_extreme": self.lost_extreme,
                "sphere_structure": self.structure.value, "sphere_kept_structure": self.kept_structure.value}


def empty_sphere_causes() -> dict[str, Any]:
    """The columns of a row without a projection (sphere off, or preprocessing failed)."""
    return {"sphere_extreme": None, "sphere_lost_extreme": None, "sphere_structure": "", "sphere_kept_structure": ""}


def lost_extreme(points: np.ndarray, extreme: np.ndarray, surface: np.ndarray) -> int:
    """How many of the extreme points ``points[extreme]`` have coordinates outside ``points[surface]``.

    Parameters
    ----------
    points : ndarray of shape (n, d), float64
    extreme : ndarray of int
        Rows of the input's extreme points, one per distinct coordinate.
    surface : ndarray of int
        Rows the sphere method kept (its surface list).

    Examples
    --------
    >>> pts = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.0, 0.0]])
    >>> lost_extreme(pts, np.array([0, 1, 2]), np.array([3, 1]))  # row 3 repeats row 0
    1
    """
    from .checker.extreme import rows_in

    pts = np.asarray(points)
    return int((~rows_in(pts[np.asarray(extreme, dtype=np.int64)], pts[np.asarray(surface, dtype=np.int64)])).sum())


# One projection serves every algorithm of a case with the same duplicate tolerance.
_CACHE: OrderedDict[tuple[str, str], SphereCauses] = OrderedDict()
_CACHE_SIZE = 8


def sphere_causes(
    points: np.ndarray,
    reference: Any,
    projected_reference: Any,
    index_map: np.ndarray,
    verdict_of: Callable[[Any], Any],
    *,
    duplicate_eps: float,
    cache_key: tuple[str, str] | None = None,
) -> SphereCauses:
    """Measure vertex loss and face-structure change of one sphere projection.

    Parameters
    ----------
    points : ndarray of shape (n, d), float64
        The input points.
    reference : QhullReference or None
        The input's reference (its ``extreme`` is the certified extreme set).
    projected_reference : QhullReference or None
        The reference of the method's projected points.
    index_map : ndarray of int64
        Row ``i`` of the projected points is input row ``index_map[i]``.
    verdict_of : callable
        ``verdict_of(faces)`` is the exact verdict on ``faces`` (in input rows)
        as the input's hull (the same judge as the sphere method's verdict).
    duplicate_eps : float
        The method's duplicate tolerance (it decides the centroid).
    cache_key : tuple of str, optional
        Identifies (input, projection); a repeated key returns the stored result.

    Returns
    -------
    SphereCauses
        A structure is ``unknown`` when there is no certified hull to map
        back (Qhull's fails the exact checks, both sets are affinely
        degenerate, a reference is missing, or a true vertex cannot be
        projected), ``error`` when the checker raised on the mapped-back hull.
    """
    if cache_key is not None and cache_key in _CACHE:
        _CACHE.move_to_end(cache_key)
        return _CACHE[cache_key]
    extreme_rows = getattr(reference, "extreme", None)
    extreme = lost = None
    kept = SphereStructure.UNKNOWN
    if extreme_rows is not None:
        extreme, lost = len(extreme_rows), lost_extreme(points, extreme_rows, index_map)
        kept = _kept_structure(points, np.asarray(extreme_rows, dtype=np.int64), reference, duplicate_eps,
                               verdict_of)
    causes = SphereCauses(extreme, lost, _structure(reference, projected_reference, index_map, verdict_of), kept)
    if cache_key is not None:
        _CACHE[cache_key] = causes
        while len(_CACHE) > _CACHE_SIZE:
            _CACHE.popitem(last=False)
    return causes


def _kept_structure(points: np.ndarray, extreme_rows: np.ndarray, reference: Any, duplicate_eps: float,
                    verdict_of: Callable[[Any], Any]) -> SphereStructure:
    """The structure of the projection of exactly the true extreme points, from the method's centroid."""
    from .checker import qhull_reference
    from .sphere import project_onto_sphere, sphere_centroid

    try:
        projected = project_onto_sphere(points, extreme_rows, sphere_centroid(points, eps=duplicate_eps))
    except ValueError:  # a vertex at the centroid, or squares that underflow: no projection to judge
        return SphereStructure.UNKNOWN
    if not np.isfinite(projected).all():
        return SphereStructure.UNKNOWN
    return _structure(reference, qhull_reference(projected), extreme_rows, verdict_of)


def _structure(reference: Any, projected_reference: Any, index_map: np.ndarray,
               verdict_of: Callable[[Any], Any]) -> SphereStructure:
    from .sphere import map_back

    rank = getattr(reference, "affine_rank", None)
    projected_rank = getattr(projected_reference, "affine_rank", None)
    if rank is None or projected_rank is None:
        return SphereStructure.UNKNOWN
    if projected_rank < rank:  # the hull of a flatter set cannot map back to the input's hull
        return SphereStructure.CHANGED
    if projected_rank < projected_reference.dim or not projected_reference.qhull_ok:
        return SphereStructure.UNKNOWN
    try:
        verdict = verdict_of(map_back(projected_reference.faces, index_map))
    except Exception:  # a checker bug here must not change the row's own verdict; it is recorded
        return SphereStructure.ERROR
    return SphereStructure.SAME if verdict.ok else SphereStructure.CHANGED
