"""Qhull through ``scipy.spatial.ConvexHull``, under several option sets.

Each option set is its own registered algorithm, so a sweep shows which
Qhull options survive which degeneracies:

=========================  ===  ===================  ==========================================
name                       dim  ``qhull_options``    what it is
=========================  ===  ===================  ==========================================
scipy-qhull-2d             2    ``None``             scipy's default (Qhull defaults plus Qt)
scipy-qhull-2d-QJ          2    ``"QJ"``             joggled input: never a precision error
scipy-qhull-3d             3    ``None``             scipy's default (Qhull defaults plus Qt)
scipy-qhull-3d-QJ          3    ``"QJ"``             joggled input
scipy-qhull-3d-Qt-Qc       3    ``"Qt Qc"``          triangulated, coplanar points kept
scipy-qhull-3d-Q12         3    ``"Q12"``            allow wide facets and wide dupridges
scipy-qhull-3d-Q0          3    ``"Q0"``             no pre-merging: precision problems surface
scipy-qhull-3d-QbB-Pp      3    ``"QbB Pp"``         trimesh's options: scaled to the unit cube
=========================  ===  ===================  ==========================================

scipy always adds ``Qt`` (triangulated output) unless ``QJ`` is given, so the
3D results are triangles.  Qt and Qc change nothing in 2D and Q12 is about
3D ridges, so the 2D list is shorter.

Output orientation
------------------
In 2D, ``ConvexHull.vertices`` is counter-clockwise already.  In 3D,
``ConvexHull.simplices`` is not consistently oriented; :func:`orient_simplices`
orients it.  It does not flip each triangle by the sign of its normal against
``hull.equations``: Qt may emit zero-area triangles (in merged coplanar
facets), whose float normal has a meaningless sign.  Instead it orients one
well-conditioned triangle by its outward normal and propagates that
orientation across Qhull's facet adjacency (``hull.neighbors``), which
recovers Qhull's own topological orientation.

Errors
------
These adapters take no ``eps`` (Qhull has its own tolerances).  A
``QhullError`` (e.g. "initial simplex is flat" on coplanar input) is not
caught: the harness records it as ``rejected`` on degenerate input and as
``error`` otherwise.

Declared contract
-----------------
``faces=triangles`` in 3D (scipy documents ``simplices`` as "the simplical
facets of the convex hull"), otherwise lenient: Qhull documents its output as
convex only within roundoff ("Imprecision in Qhull", qh-impre.htm), so a
vertex a rounding error inside a facet is within its promise (vertices stay
``boundary``); and although Qhull raises QH6154 "initial simplex is flat" on
flat input, it decides flatness in floating point, so an exactly flat input
may be answered (``flat=either``).  See ``docs/contracts.md``.

Examples
--------
>>> import numpy as np
>>> square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.5, 0.5]])
>>> scipy_qhull_2d(square).tolist()
[0, 1, 2, 3]
"""

from __future__ import annotations

import math
from collections import deque

import numpy as np
from scipy.spatial import ConvexHull

from .._registry import register_algorithm

__all__ = [
    "ALGORITHM_NAMES",
    "QHULL_OPTIONS",
    "qhull_2d",
    "qhull_3d",
    "orient_simplices",
    "scipy_qhull_2d",
    "scipy_qhull_2d_qj",
    "scipy_qhull_3d",
    "scipy_qhull_3d_qj",
    "scipy_qhull_3d_qt_qc",
    "scipy_qhull_3d_q12",
    "scipy_qhull_3d_q0",
    "scipy_qhull_3d_qbb_pp",
]

#: What the 3D adapters promise (see "Declared contract" above); 2D: lenient.
QHULL_3D_CONTRACT = "faces=triangles"

#: Registered name -> the ``qhull_options`` string passed to scipy (None: scipy's default).
QHULL_OPTIONS: dict[str, str | None] = {
    "scipy-qhull-2d": None,
    "scipy-qhull-2d-QJ": "QJ",
    "scipy-qhull-3d": None,
    "scipy-qhull-3d-QJ": "QJ",
    "scipy-qhull-3d-Qt-Qc": "Qt Qc",
    "scipy-qhull-3d-Q12": "Q12",
    "scipy-qhull-3d-Q0": "Q0",
    "scipy-qhull-3d-QbB-Pp": "QbB Pp",
}

#: The algorithm names this module registers.
ALGORITHM_NAMES: tuple[str, ...] = tuple(QHULL_OPTIONS)


def qhull_2d(points: np.ndarray, options: str | None) -> np.ndarray:
    """Qhull's 2D hull as counter-clockwise vertex indices.

    Parameters
    ----------
    points : ndarray of shape (n, 2), float64
    options : str or None
        ``qhull_options`` for ``scipy.spatial.ConvexHull`` (None: scipy's default).

    Returns
    -------
    ndarray of shape (k,), int64

    Raises
    ------
    scipy.spatial.QhullError
        When Qhull declines, e.g. on collinear input without ``QJ``.

    Examples
    --------
    >>> import numpy as np
    >>> qhull_2d(np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 2.0], [0.5, 0.5]]), None).tolist()
    [0, 1, 2]
    >>> try:
    ...     qhull_2d(np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]), None)
    ... except Exception as exc:
    ...     print(type(exc).__name__)
    QhullError
    """
    hull = ConvexHull(points, qhull_options=options)
    return np.asarray(hull.vertices, dtype=np.int64)


def qhull_3d(points: np.ndarray, options: str | None) -> np.ndarray:
    """Qhull's 3D hull as triangles, counter-clockwise seen from outside.

    Parameters
    ----------
    points : ndarray of shape (n, 3), float64
    options : str or None
        ``qhull_options`` for ``scipy.spatial.ConvexHull`` (None: scipy's default).

    Returns
    -------
    ndarray of shape (m, 3), int64

    Raises
    ------
    scipy.spatial.QhullError
        When Qhull declines, e.g. on coplanar input without ``QJ``.

    Examples
    --------
    >>> import numpy as np
    >>> tet = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    >>> qhull_3d(tet, None).shape
    (4, 3)
    """
    hull = ConvexHull(points, qhull_options=options)
    return orient_simplices(points, hull.simplices, hull.neighbors, hull.equations[:, :3])


def orient_simplices(
    points: np.ndarray,
    simplices: np.ndarray,
    neighbors: np.ndarray,
    normals: np.ndarray,
) -> np.ndarray:
    """Orient Qhull's 3D triangles consistently and outward.

    In each connected component the triangle whose geometric normal agrees
    best (largest cosine) with Qhull's outward facet normal is oriented by
    that normal; every other triangle takes the orientation that traverses
    the shared edge opposite to its already oriented neighbour.  Breadth-first
    order; each triangle is oriented once.

    Parameters
    ----------
    points : ndarray of shape (n, 3), float64
    simplices : ndarray of shape (m, 3), int
        ``ConvexHull.simplices``.
    neighbors : ndarray of shape (m, 3), int
        ``ConvexHull.neighbors``: ``neighbors[i, k]`` is the triangle opposite
        vertex ``k`` of triangle ``i`` (-1 for none).
    normals : ndarray of shape (m, 3), float64
        Outward facet normals, ``ConvexHull.equations[:, :3]``.

    Returns
    -------
    ndarray of shape (m, 3), int64
        ``simplices`` with some rows' last two entries swapped.

    Examples
    --------
    A tetrahedron given with every triangle clockwise comes back counter-clockwise:

    >>> import numpy as np
    >>> p = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    >>> tri = np.array([[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]])
    >>> nbr = np.array([[3, 2, 1], [3, 0, 2], [3, 1, 0], [2, 0, 1]])
    >>> nrm = np.array([[0.0, 0, -1], [0, -1, 0], [-1, 0, 0], [1, 1, 1]])
    >>> orient_simplices(p, tri, nbr, nrm).tolist()
    [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]
    """
    tri = np.array(simplices, dtype=np.int64).reshape(-1, 3)
    m = len(tri)
    if m == 0:
        return tri
    pts = np.asarray(points, dtype=np.float64)
    # An exact power-of-two scaling (signs unchanged) so the largest coordinate lies in [0.5, 1):
    # at 1e-300 every edge cross product underflows to 0 (and overflows near 1e300), which left
    # the seed triangle unoriented and half such hulls inside out.
    finite = np.abs(pts[np.isfinite(pts)])
    if finite.size and finite.max() > 0:
        pts = np.ldexp(pts, -math.frexp(float(finite.max()))[1])
    a, b, c = pts[tri[:, 0]], pts[tri[:, 1]], pts[tri[:, 2]]
    cross = np.cross(b - a, c - a)
    normals = np.asarray(normals, dtype=np.float64)
    score = np.einsum("ij,ij->i", cross, normals)
    scale = np.linalg.norm(cross, axis=1) * np.linalg.norm(normals, axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        cosine = np.where(scale > 0, np.abs(score) / scale, 0.0)
    flip = np.zeros(m, dtype=bool)
    done = np.zeros(m, dtype=bool)
    tri_list = tri.tolist()  # Python ints: the walk below is scalar code
    nbr_list = np.asarray(neighbors, dtype=np.int64).reshape(-1, 3).tolist()
    # Seeds in order of decreasing confidence; only unvisited ones start a component.
    for seed in np.argsort(-cosine, kind="stable").tolist():
        if done[seed]:
            continue
        done[seed] = True
        flip[seed] = score[seed] < 0
        queue = deque([seed])
        while queue:
            i = queue.popleft()
            u0, u1, u2 = tri_list[i]
            order = (u0, u2, u1) if flip[i] else (u0, u1, u2)
            for k, j in enumerate(nbr_list[i]):
                if j < 0 or done[j]:
                    continue
                # The shared edge is the two vertices other than tri[i][k], in i's oriented order.
                pos = order.index(tri_list[i][k])
                edge = (order[(pos + 1) % 3], order[(pos + 2) % 3])  # i traverses edge[0] -> edge[1]
                x0, x1, x2 = tri_list[j]
                flip[j] = edge in ((x0, x1), (x1, x2), (x2, x0))  # j must traverse it backwards
                done[j] = True
                queue.append(j)
    out = tri.copy()
    out[flip, 1], out[flip, 2] = tri[flip, 2], tri[flip, 1]
    return out


@register_algorithm("scipy-qhull-2d", dim=2)
def scipy_qhull_2d(points: np.ndarray, /) -> np.ndarray:
    """Qhull via scipy.spatial.ConvexHull, scipy's default options (2D)."""
    return qhull_2d(points, QHULL_OPTIONS["scipy-qhull-2d"])


@register_algorithm("scipy-qhull-2d-QJ", dim=2)
def scipy_qhull_2d_qj(points: np.ndarray, /) -> np.ndarray:
    """Qhull via scipy.spatial.ConvexHull with QJ: joggled input (2D)."""
    return qhull_2d(points, QHULL_OPTIONS["scipy-qhull-2d-QJ"])


@register_algorithm("scipy-qhull-3d", dim=3, contract=QHULL_3D_CONTRACT)
def scipy_qhull_3d(points: np.ndarray, /) -> np.ndarray:
    """Qhull via scipy.spatial.ConvexHull, scipy's default options (3D, Qt)."""
    return qhull_3d(points, QHULL_OPTIONS["scipy-qhull-3d"])


@register_algorithm("scipy-qhull-3d-QJ", dim=3, contract=QHULL_3D_CONTRACT)
def scipy_qhull_3d_qj(points: np.ndarray, /) -> np.ndarray:
    """Qhull via scipy.spatial.ConvexHull with QJ: joggled input (3D)."""
    return qhull_3d(points, QHULL_OPTIONS["scipy-qhull-3d-QJ"])


@register_algorithm("scipy-qhull-3d-Qt-Qc", dim=3, contract=QHULL_3D_CONTRACT)
def scipy_qhull_3d_qt_qc(points: np.ndarray, /) -> np.ndarray:
    """Qhull via scipy.spatial.ConvexHull with Qt Qc: triangulated, coplanar points kept (3D)."""
    return qhull_3d(points, QHULL_OPTIONS["scipy-qhull-3d-Qt-Qc"])


@register_algorithm("scipy-qhull-3d-Q12", dim=3, contract=QHULL_3D_CONTRACT)
def scipy_qhull_3d_q12(points: np.ndarray, /) -> np.ndarray:
    """Qhull via scipy.spatial.ConvexHull with Q12: wide facets and dupridges allowed (3D)."""
    return qhull_3d(points, QHULL_OPTIONS["scipy-qhull-3d-Q12"])


@register_algorithm("scipy-qhull-3d-Q0", dim=3, contract=QHULL_3D_CONTRACT)
def scipy_qhull_3d_q0(points: np.ndarray, /) -> np.ndarray:
    """Qhull via scipy.spatial.ConvexHull with Q0: no pre-merging of facets (3D)."""
    return qhull_3d(points, QHULL_OPTIONS["scipy-qhull-3d-Q0"])


@register_algorithm("scipy-qhull-3d-QbB-Pp", dim=3, contract=QHULL_3D_CONTRACT)
def scipy_qhull_3d_qbb_pp(points: np.ndarray, /) -> np.ndarray:
    """Qhull via scipy.spatial.ConvexHull with QbB Pp, trimesh's options (3D)."""
    return qhull_3d(points, QHULL_OPTIONS["scipy-qhull-3d-QbB-Pp"])
