"""Run every exact check on one surface: the certificate behind a verdict.

:func:`certify` runs on the output under test (by
:func:`hullstress.checker.check`) and on Qhull's own hull (by
:func:`hullstress.checker.qhull_reference`, for ``qhull_ok``); a closed
triangle mesh that is convex is certified in one batch
(:mod:`.closed_mesh`), anything else by the general checks below.  It works on
points already rescaled by :func:`._geometry.exact_scale`, so magnitudes and
the volume come out in scaled units.
"""

from __future__ import annotations

import numpy as np

from ..contract import FaceSet
from ._geometry import triangle_array
from .certificate import Certificate, corners3
from .closed_mesh import certify_closed_mesh, certify_convex_polygon
from .containment import check_containment2d, check_containment3d
from .convexity3d import check_convexity3d
from .measure import surface_measure
from .polygon2d import check_polygon2d
from .topology import check_topology, half_edges

__all__ = ["Certificate", "certify"]


def certify(points: np.ndarray, faces: np.ndarray | FaceSet, *, seed: int = 0, batched: bool = True) -> Certificate:
    """Run containment, convexity and manifoldness exactly, and classify the vertices.

    The interior point of the convexity check comes from the surface's own
    vertices (their mean, or the exact centroid of a simplex of them):
    convexity is a property of the surface alone, containment the one that
    involves the other input points.

    Parameters
    ----------
    points : ndarray of shape (n, d), float64
        Finite; ideally rescaled with :func:`._geometry.exact_scale`.
    faces : ndarray of shape (k,), int64 (2D) or FaceSet (3D)
        Normalised output (:func:`hullstress.contract.normalize_output`).
    seed : int
        For the ray of the wrap-number tests; the verdict does not depend on it.
    batched : bool
        Try :func:`.closed_mesh.certify_closed_mesh` first on triangle meshes
        (it certifies or declines; false runs only the general checks, for tests).

    Returns
    -------
    Certificate
    """
    dim = points.shape[1]
    if dim == 2:
        poly = np.asarray(faces, dtype=np.int64)
        if batched:
            quick = certify_convex_polygon(points, poly, seed=seed)
            if quick is not None:
                return quick
        return _certify2(points, poly, seed)
    if batched and triangle_array(faces) is not None:
        quick = certify_closed_mesh(points, faces, seed=seed)
        if quick is not None:
            return quick
    return _certify3(points, faces, seed)


def _certify3(points: np.ndarray, faces: FaceSet, seed: int) -> Certificate:
    he = half_edges(faces, len(points))
    measure = surface_measure(points, faces)
    topo = check_topology(points, faces, he=he, measure=measure)
    conv = check_convexity3d(points, faces, he, closed=topo.ok, seed=seed)
    cont = check_containment3d(
        points, faces, conv.plane, certified=topo.ok and conv.ok, center=conv.center, he=he
    )
    vertices = np.unique(faces.indices)
    extreme = boundary = None
    if topo.ok and conv.ok and cont.ok:
        extreme = corners3(points, vertices, conv.sharp_edges)
        boundary = np.setdiff1d(vertices, extreme)
    offending = {
        "containment": cont.outside,
        "degenerate_faces": np.flatnonzero(conv.degenerate),
        "reflex_faces": conv.reflex_faces,
        "flipped_faces": conv.flipped,
        "manifold_faces": topo.bad_faces,
        "manifold_vertices": topo.bad_vertices,
    }
    mags = dict(conv.magnitudes)
    if cont.outside.size:
        mags["outside"] = cont.magnitude
    return Certificate(
        dim=3,
        containment=cont.ok,
        convexity=conv.ok,
        manifoldness=topo.ok,
        n_faces=faces.n_faces,
        hull_vertices=vertices,
        extreme=extreme,
        boundary_nonextreme=boundary,
        outside=cont.outside,
        n_nonconvex_edges=conv.n_reflex_edges,
        n_degenerate_faces=int(conv.degenerate.sum()),
        offending=offending,
        magnitudes=mags,
        measure=measure,
        reasons={"containment": [f"{cont.outside.size} points outside"] if cont.outside.size else [], "convexity": conv.reasons, "manifoldness": topo.reasons},
        wraps=conv.degree,
    )


def _certify2(points: np.ndarray, poly: np.ndarray, seed: int) -> Certificate:
    measure = surface_measure(points, poly)
    pg = check_polygon2d(points, poly, seed=seed, measure=measure)
    cont = check_containment2d(points, poly, certified=pg.manifold_ok and pg.convex_ok, center=pg.center)
    vertices = np.unique(poly)
    extreme = boundary = None
    if pg.manifold_ok and pg.convex_ok and cont.ok:
        extreme = np.unique(poly[pg.turn > 0])
        boundary = np.unique(poly[pg.turn == 0])
    offending = {
        "containment": cont.outside,
        "degenerate_edges": pg.degenerate_edges,
        "reflex_vertices": poly[pg.reflex] if len(poly) else pg.reflex,
        "flipped_edges": pg.flipped,
        "manifold_vertices": poly[pg.bad_vertices] if len(poly) else pg.bad_vertices,
    }
    mags = dict(pg.magnitudes)
    if cont.outside.size:
        mags["outside"] = cont.magnitude
    return Certificate(
        dim=2,
        containment=cont.ok,
        convexity=pg.convex_ok,
        manifoldness=pg.manifold_ok,
        n_faces=len(poly),
        hull_vertices=vertices,
        extreme=extreme,
        boundary_nonextreme=boundary,
        outside=cont.outside,
        n_nonconvex_edges=len(pg.reflex),
        n_degenerate_faces=len(pg.degenerate_edges),
        offending=offending,
        magnitudes=mags,
        measure=measure,
        reasons={"containment": [f"{cont.outside.size} points outside"] if cont.outside.size else [], "convexity": pg.reasons_convex, "manifoldness": pg.reasons_manifold},
        wraps=pg.wraps,
    )
