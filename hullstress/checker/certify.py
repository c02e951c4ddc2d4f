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
from .convexity3d import check_convexity3d, face_planes
from .measure import surface_measure
from .polygon2d import check_polygon2d
from .topology import check_topology, half_edges
from ._unique import unique_ints

__all__ = ["Certificate", "certify"]

#: Corners (face-vertex slots) up to which an oversized answer still gets the general checks and
#: their detailed reasons; beyond, :func:`oversized` answers are judged in linear time.
_FULL_CHECKS_UP_TO = 30_000


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
    if len(faces.indices) > _FULL_CHECKS_UP_TO and oversized(faces, len(points)):
        return _certify3_oversized(points, faces)
    if batched and triangle_array(faces) is not None:
        quick = certify_closed_mesh(points, faces, seed=seed)
        if quick is not None:
            return quick
    return _certify3(points, faces, seed)


def oversized(faces: FaceSet, n_points: int) -> bool:
    """Whether a 3D answer has more faces or corners than any convex hull of ``n_points`` points.

    The boundary of a convex polytope is a sphere; with ``V <= n`` vertices
    (one index per coordinate), Euler's formula gives at most ``2V - 4``
    faces, and, faces having at least three edges, ``2E = sum of face sizes
    <= 6V - 12``.  An answer beyond either bound is no valid hull whatever its
    geometry (a gift-wrap that loops can emit 78,605 triangles over 1024
    points, issue 33 F9).
    """
    return faces.n_faces > max(2 * n_points - 4, 4) or len(faces.indices) > max(6 * n_points - 12, 12)


def _certify3_oversized(points: np.ndarray, faces: FaceSet) -> Certificate:
    """The certificate of an answer :func:`oversized` rules out, in time linear in its size.

    Manifoldness fails (no sphere over at most n vertices has that many
    faces), and convexity with it (a closed surface that is convex around an
    interior point and wraps it once is such a sphere).  Containment is still
    decided exactly, on the answer's distinct face planes, streamed in chunks.
    """
    n = len(points)
    plane = face_planes(points, faces)
    distinct = np.unique(plane[plane[:, 0] >= 0], axis=0)
    cont = check_containment3d(points, faces, distinct)
    why = (f"{faces.n_faces} faces with {len(faces.indices)} corners: more than any convex hull of {n} points has "
           f"(at most {2 * n - 4} faces, {6 * n - 12} corners); not judged further")
    empty = np.zeros(0, np.int64)
    mags = {"outside": cont.magnitude} if cont.outside.size else {}
    return Certificate(
        dim=3,
        containment=cont.ok,
        convexity=False,
        manifoldness=False,
        n_faces=faces.n_faces,
        hull_vertices=unique_ints(faces.indices),
        extreme=None,
        boundary_nonextreme=None,
        outside=cont.outside,
        n_nonconvex_edges=0,
        n_degenerate_faces=int(np.count_nonzero(plane[:, 0] < 0)),
        offending={"containment": cont.outside, "degenerate_faces": empty, "reflex_faces": empty,
                   "flipped_faces": empty, "manifold_faces": empty, "manifold_vertices": empty},
        magnitudes=mags,
        measure=surface_measure(points, faces),  # linear in the answer's size; the Qhull comparison reads it
        reasons={"containment": [f"{cont.outside.size} points outside"] if cont.outside.size else [],
                 "convexity": ["too many faces for a closed convex surface"], "manifoldness": [why]},
        wraps=None,
    )


def _certify3(points: np.ndarray, faces: FaceSet, seed: int) -> Certificate:
    he = half_edges(faces, len(points))
    measure = surface_measure(points, faces)
    topo = check_topology(points, faces, he=he, measure=measure)
    conv = check_convexity3d(points, faces, he, closed=topo.ok, seed=seed)
    cont = check_containment3d(
        points, faces, conv.plane, certified=topo.ok and conv.ok, center=conv.center, he=he
    )
    vertices = unique_ints(faces.indices)
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
    vertices = unique_ints(poly)
    extreme = boundary = None
    if pg.manifold_ok and pg.convex_ok and cont.ok:
        extreme = unique_ints(poly[pg.turn > 0])
        boundary = unique_ints(poly[pg.turn == 0])
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
