"""Run every exact check on one surface: the certificate behind a verdict.

:func:`certify` is used twice per case: on the output under test (by
:func:`hullstress.checker.check`) and on Qhull's own hull (by
:func:`hullstress.checker.qhull_reference`, for ``qhull_ok``).  It works on
points already rescaled by :func:`._geometry.exact_scale`, so magnitudes and
the volume come out in scaled units.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..contract import FaceSet
from ._geometry import Interior
from .containment import check_containment2d, check_containment3d
from .convexity3d import check_convexity3d
from .polygon2d import check_polygon2d
from .predicates import collinear3d, orient2d_value, orient3d_value
from .rank import witness_simplex
from .topology import check_topology, half_edges

__all__ = ["Certificate", "certify"]


@dataclass
class Certificate:
    """The exact findings on one surface.

    Attributes
    ----------
    dim : int
    containment, convexity, manifoldness : bool
    n_faces : int
        Faces (3D) or edges (2D).
    hull_vertices : ndarray of int64
        Distinct vertex indices used by the surface.
    extreme : ndarray of int64 or None
        The surface's corners (strictly convex vertices) when it is certified
        (all three checks pass), which are then exactly the extreme points of
        the input; None otherwise.
    boundary_nonextreme : ndarray of int64 or None
        Certified surfaces only: vertices on an edge or face but not corners.
    outside : ndarray of int64
    n_nonconvex_edges, n_degenerate_faces : int
    offending : dict of str to ndarray
        Full (untruncated) offending indices per kind.
    magnitudes : dict of str to float
        Largest violation distance per kind, in scaled units.
    volume : float
        Volume (area in 2D) in scaled units, float.
    reasons : dict of str to list of str
        Per check, what failed.
    """

    dim: int
    containment: bool
    convexity: bool
    manifoldness: bool
    n_faces: int
    hull_vertices: np.ndarray
    extreme: np.ndarray | None
    boundary_nonextreme: np.ndarray | None
    outside: np.ndarray
    n_nonconvex_edges: int
    n_degenerate_faces: int
    offending: dict[str, np.ndarray] = field(default_factory=dict)
    magnitudes: dict[str, float] = field(default_factory=dict)
    volume: float = 0.0
    reasons: dict[str, list[str]] = field(default_factory=dict)

    @property
    def certified(self) -> bool:
        return self.containment and self.convexity and self.manifoldness


def _volume3(points: np.ndarray, faces: FaceSet) -> float:
    tri, _ = faces.fan_triangles()
    if not len(tri):
        return 0.0
    ref = points[tri[0, 0]]
    vals = orient3d_value(points[tri[:, 0]], points[tri[:, 1]], points[tri[:, 2]], ref)
    return math.fsum(np.nan_to_num(vals).tolist()) / 6.0


def _corners3(points: np.ndarray, vertices: np.ndarray, sharp: np.ndarray) -> np.ndarray:
    """Corners of a certified convex surface, from its sharp (non-flat) edges.

    On the boundary of a convex polytope a vertex with no sharp edge lies
    inside a flat region, one with exactly two collinear sharp edges on either
    side lies inside an edge of the polytope, and a corner has at least three.
    """
    n = len(points)
    count = np.bincount(sharp.ravel(), minlength=n) if sharp.size else np.zeros(n, np.int64)
    is_corner = count[vertices] >= 3
    two = vertices[count[vertices] == 2]
    if two.size:
        # The two sharp neighbours of each such vertex.
        ends = np.concatenate([sharp, sharp[:, ::-1]])
        ends = ends[np.isin(ends[:, 0], two)]
        ends = ends[np.lexsort((ends[:, 1], ends[:, 0]))]
        v = ends[0::2, 0]
        x, y = ends[0::2, 1], ends[1::2, 1]
        px, pv, py = points[x], points[v], points[y]
        between = collinear3d(px, pv, py) & np.any((px - pv) * (py - pv) < 0, axis=1)
        corner_two = v[~between]
        is_corner |= np.isin(vertices, corner_two)
    is_corner |= count[vertices] == 1  # impossible on a convex surface; kept as a corner, not dropped
    return vertices[is_corner]


def surface_interior(points: np.ndarray, vertices: np.ndarray) -> Interior | None:
    """The exact centroid of a non-degenerate simplex of the surface's own vertices.

    A closed convex surface has it strictly below every facet; a surface whose
    vertices are affinely degenerate (flat) has none, and cannot be convex.
    """
    dim = points.shape[1]
    if not len(vertices):
        return None
    simplex = vertices[witness_simplex(points[vertices])]
    return Interior.from_simplex(points[simplex]) if len(simplex) == dim + 1 else None


def certify(points: np.ndarray, faces: np.ndarray | FaceSet, *, seed: int = 0) -> Certificate:
    """Run containment, convexity and manifoldness exactly, and classify the vertices.

    The interior point of the convexity check is the exact centroid of a
    non-degenerate simplex of the surface's own vertices
    (:func:`surface_interior`): convexity is a property of the surface alone,
    containment the one that involves the other input points.

    Parameters
    ----------
    points : ndarray of shape (n, d), float64
        Finite; ideally rescaled with :func:`._geometry.exact_scale`.
    faces : ndarray of shape (k,), int64 (2D) or FaceSet (3D)
        Normalised output (:func:`hullstress.contract.normalize_output`).
    seed : int
        For the random rays of the degree tests; the verdict does not depend on it.

    Returns
    -------
    Certificate
    """
    dim = points.shape[1]
    if dim == 2:
        poly = np.asarray(faces, dtype=np.int64)
        return _certify2(points, poly, surface_interior(points, np.unique(poly)), seed)
    return _certify3(points, faces, surface_interior(points, np.unique(faces.indices)), seed)


def _certify3(points: np.ndarray, faces: FaceSet, interior: Interior | None, seed: int) -> Certificate:
    he = half_edges(faces, len(points))
    topo = check_topology(points, faces)
    conv = check_convexity3d(points, faces, he, interior, closed=topo.ok, seed=seed)
    cont = check_containment3d(
        points, faces, conv.plane, certified=topo.ok and conv.ok, center=conv.center, he=he
    )
    vertices = np.unique(faces.indices)
    extreme = boundary = None
    if topo.ok and conv.ok and cont.ok:
        extreme = _corners3(points, vertices, conv.sharp_edges)
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
        volume=_volume3(points, faces),
        reasons={"containment": [f"{cont.outside.size} points outside"] if cont.outside.size else [], "convexity": conv.reasons, "manifoldness": topo.reasons},
    )


def _certify2(points: np.ndarray, poly: np.ndarray, interior: Interior | None, seed: int) -> Certificate:
    pg = check_polygon2d(points, poly, interior, seed=seed)
    cont = check_containment2d(points, poly, certified=pg.manifold_ok and pg.convex_ok, center=pg.center)
    vertices = np.unique(poly)
    extreme = boundary = None
    if pg.manifold_ok and pg.convex_ok and cont.ok:
        extreme = np.unique(poly[pg.turn > 0])
        boundary = np.unique(poly[pg.turn == 0])
    area = 0.0
    if len(poly) >= 3:
        a, b = points[poly], points[np.roll(poly, -1)]
        area = math.fsum(np.nan_to_num(orient2d_value(a, b, a[0])).tolist()) / 2.0
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
        volume=area,
        reasons={"containment": [f"{cont.outside.size} points outside"] if cont.outside.size else [], "convexity": pg.reasons_convex, "manifoldness": pg.reasons_manifold},
    )
