"""Convexity of a 3D surface, decided with exact predicates (DESIGN.md "Verdict semantics").

A surface is convex when

1. every face is non-degenerate: a triangle whose vertices are not collinear;
   a polygon with distinct vertex coordinates, planar (every vertex on the
   plane of a non-collinear triple) and convex (in a coordinate projection
   where that triple does not collapse, every vertex is on the inner side of
   every edge: all O(k^2) pairs are tested, which also rules out polygons
   that wind twice);
2. across every edge, no vertex of the neighbouring face is strictly above
   the face's plane (no reflex edge);
3. one interior point (the exact centroid of a non-degenerate simplex of
   the surface's own vertices, strictly inside their hull) is strictly below
   every face;
4. when the surface is a closed oriented manifold, a ray from that interior
   point crosses it exactly once (the radial projection has degree 1).  With
   1-3 this rules out a locally convex surface that wraps twice around the
   interior point, which 1-3 alone cannot see (a branched double cover).

Each violation also gets a float magnitude (a distance) for the severity.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..contract import FaceSet
from ._geometry import Interior, point_line_distance, point_plane_distance
from .predicates import collinear3d, orient2d, orient3d, orient3d_mean
from .topology import HalfEdges

__all__ = ["Convexity3D", "face_planes", "check_convexity3d"]


@dataclass
class Convexity3D:
    """What the 3D convexity check found.

    Attributes
    ----------
    ok : bool
    plane : ndarray of shape (m, 3), int64
        A non-collinear vertex triple spanning each face's plane, in the
        face's order (-1 where the face has none).
    degenerate : ndarray of shape (m,), bool
        Faces that are collinear, repeat a vertex, or are non-planar or
        non-convex polygons.
    reflex_faces : ndarray of int64
        Faces on either side of a reflex edge.
    n_reflex_edges : int
    flipped : ndarray of int64
        Faces that the interior point is not strictly below.
    sharp_edges : ndarray of shape (s, 2), int64
        Undirected edges (vertex pairs) whose two faces are not coplanar.
    center : ndarray of shape (3,) or None
        A float point verified (exactly) to be strictly below every face, when
        one was found: the containment shortcut projects from it.
    degree : int or None
        Faces crossed by a ray from the interior point (None when not computed).
    magnitudes : dict of str to float
        Largest distance per violation kind (float, for reporting).
    reasons : list of str
    """

    ok: bool
    plane: np.ndarray
    degenerate: np.ndarray
    reflex_faces: np.ndarray
    n_reflex_edges: int
    flipped: np.ndarray
    sharp_edges: np.ndarray
    center: np.ndarray | None
    degree: int | None
    magnitudes: dict[str, float] = field(default_factory=dict)
    reasons: list[str] = field(default_factory=list)


def face_planes(points: np.ndarray, faces: FaceSet) -> np.ndarray:
    """The first non-collinear fan triple ``(v0, v_i, v_i+1)`` of each face, or -1."""
    tri, face_of = faces.fan_triangles()
    plane = np.full((faces.n_faces, 3), -1, dtype=np.int64)
    if not len(tri):
        return plane
    good = ~collinear3d(points[tri[:, 0]], points[tri[:, 1]], points[tri[:, 2]])
    idx = np.flatnonzero(good)
    faces_with, first = np.unique(face_of[idx], return_index=True)
    plane[faces_with] = tri[idx[first]]
    return plane


def _polygon_defects(points: np.ndarray, faces: FaceSet, plane: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Non-planar, non-convex or duplicate-coordinate polygons (k > 3) and their magnitudes."""
    m = faces.n_faces
    bad = np.zeros(m, dtype=bool)
    mag = np.zeros(m)
    big = np.flatnonzero((faces.sizes > 3) & (plane[:, 0] >= 0))
    if not big.size:
        return bad, mag
    sizes = faces.sizes[big]
    corner_face = np.repeat(big, sizes)
    corner_vertex = np.concatenate([faces.face(f) for f in big])
    # Distinct coordinates: a polygon touching itself is not a convex polygon.
    coords = points[corner_vertex]
    order = np.lexsort((coords[:, 2], coords[:, 1], coords[:, 0], corner_face))
    same = (corner_face[order][1:] == corner_face[order][:-1]) & np.all(coords[order][1:] == coords[order][:-1], axis=1)
    bad[np.unique(corner_face[order][1:][same])] = True
    # Planarity.
    tri = plane[corner_face]
    a, b, c = points[tri[:, 0]], points[tri[:, 1]], points[tri[:, 2]]
    off = orient3d(a, b, c, coords) != 0
    if off.any():
        bad[np.unique(corner_face[off])] = True
        dist = np.abs(point_plane_distance(a[off], b[off], c[off], coords[off]))
        np.maximum.at(mag, corner_face[off], dist)
    # Convexity in a projection where the plane triple keeps its orientation.
    pa, pb, pc = points[plane[big, 0]], points[plane[big, 1]], points[plane[big, 2]]
    axes = np.full(len(big), -1)
    ref_sign = np.zeros(len(big), dtype=np.int8)
    for choice, (i, j) in enumerate(((0, 1), (1, 2), (2, 0))):
        todo = np.flatnonzero(axes < 0)
        if not todo.size:
            break
        s = orient2d(pa[todo][:, [i, j]], pb[todo][:, [i, j]], pc[todo][:, [i, j]])
        hit = s != 0
        axes[todo[hit]] = choice
        ref_sign[todo[hit]] = s[hit]
    proj = np.array([(0, 1), (1, 2), (2, 0)])
    # All (edge, vertex) pairs per polygon: sum of k^2 rows.
    pair_face, pair_e, pair_w = [], [], []
    for local, f in enumerate(big):
        verts = faces.face(f)
        k = len(verts)
        e = np.repeat(np.arange(k), k)
        w = np.tile(np.arange(k), k)
        pair_face.append(np.full(k * k, local))
        pair_e.append(np.stack([verts[e], verts[(e + 1) % k]], axis=1))
        pair_w.append(verts[w])
    pf = np.concatenate(pair_face)
    pe = np.concatenate(pair_e)
    pw = np.concatenate(pair_w)
    cols = proj[axes[pf]]
    rows = np.arange(len(pf))[:, None]
    e0, e1, w2 = points[pe[:, 0]][rows, cols], points[pe[:, 1]][rows, cols], points[pw][rows, cols]
    s = orient2d(e0, e1, w2)
    wrong = s * ref_sign[pf] < 0
    if wrong.any():
        bad[np.unique(big[pf[wrong]])] = True
        dist = np.abs(point_line_distance(e0[wrong], e1[wrong], w2[wrong]))
        np.maximum.at(mag, big[pf[wrong]], dist)
    return bad, mag


def _edge_pairs(he: HalfEdges, n_points: int) -> tuple[np.ndarray, np.ndarray]:
    """Ordered pairs of half-edges (i, j) on the same undirected edge, in different faces."""
    lo = np.minimum(he.src, he.dst)
    hi = np.maximum(he.src, he.dst)
    key = lo * max(n_points, 1) + hi
    order = np.argsort(key, kind="stable")
    k = key[order]
    starts = np.flatnonzero(np.r_[True, k[1:] != k[:-1]])
    sizes = np.diff(np.r_[starts, len(k)])
    first, second = [], []
    two = starts[sizes == 2]
    first += [order[two], order[two + 1]]
    second += [order[two + 1], order[two]]
    for s, size in zip(starts[sizes > 2], sizes[sizes > 2]):
        group = order[s : s + size]
        i, j = np.meshgrid(group, group, indexing="ij")
        keep = i != j
        first.append(i[keep])
        second.append(j[keep])
    i = np.concatenate(first) if first else np.zeros(0, np.int64)
    j = np.concatenate(second) if second else np.zeros(0, np.int64)
    keep = he.face[i] != he.face[j]
    return i[keep], j[keep]


def _degree(points: np.ndarray, faces: FaceSet, side_of_ray, rng: np.random.Generator) -> int | None:
    """Faces whose cone (from the interior point) strictly contains a random ray; None if unlucky."""
    verts = faces.indices
    face = np.repeat(np.arange(faces.n_faces), faces.sizes)
    start = faces.offsets[:-1][face]
    nxt = faces.indices[start + (np.arange(len(verts)) - start + 1) % faces.sizes[face]]
    for _ in range(8):
        s = side_of_ray(points[verts], points[nxt], rng)
        inside = np.ones(faces.n_faces, dtype=bool)
        touching = np.zeros(faces.n_faces, dtype=bool)
        np.logical_and.at(inside, face, s > 0)
        np.logical_or.at(touching, face, s == 0)
        nonneg = np.ones(faces.n_faces, dtype=bool)
        np.logical_and.at(nonneg, face, s >= 0)
        if (nonneg & touching).any():
            continue  # the ray grazes an edge or a vertex: draw another one
        return int(inside.sum())
    return None


def check_convexity3d(
    points: np.ndarray,
    faces: FaceSet,
    he: HalfEdges,
    interior: Interior | None,
    *,
    closed: bool,
    seed: int = 0,
) -> Convexity3D:
    """Check DESIGN.md's convexity for a 3D surface.

    Parameters
    ----------
    points : ndarray of shape (n, 3), float64
    faces : FaceSet
    he : HalfEdges
        From :func:`hullstress.checker.topology.half_edges`.
    interior : Interior or None
        None when the surface's vertices are flat (affine rank < 3): no
        interior point exists, so the interior-point condition fails.
    closed : bool
        Whether the surface passed the manifoldness check; the degree test
        runs only then.
    seed : int
        For the random ray of the degree test (the verdict does not depend on it).

    Returns
    -------
    Convexity3D
    """
    n = len(points)
    reasons: list[str] = []
    mags: dict[str, float] = {}
    plane = face_planes(points, faces)
    no_plane = plane[:, 0] < 0
    degenerate = no_plane.copy()
    poly_bad, poly_mag = _polygon_defects(points, faces, plane)
    degenerate |= poly_bad
    if degenerate.any():
        reasons.append(f"{int(degenerate.sum())} degenerate faces")
        mags["degenerate"] = float(poly_mag.max()) if len(poly_mag) else 0.0

    # Reflex edges: the neighbouring face's plane-triple vertices off the shared edge,
    # against this face's plane.  (Vertices on the edge are on the plane exactly:
    # testing them would only send zeros to the slow exact stage.)
    i, j = _edge_pairs(he, n)
    usable = ~no_plane[he.face[i]] & ~no_plane[he.face[j]]
    i, j = i[usable], j[usable]
    fi, fj = he.face[i], he.face[j]
    far = plane[fj]
    off_edge = (far != he.src[i][:, None]) & (far != he.dst[i][:, None])
    row, col = np.nonzero(off_edge)
    pi = plane[fi[row]]
    sign = orient3d(points[pi[:, 0]], points[pi[:, 1]], points[pi[:, 2]], points[far[row, col]])
    worst = np.full(len(fi), 2, dtype=np.int8)  # smallest sign over the far vertices
    best = np.full(len(fi), -2, dtype=np.int8)
    np.minimum.at(worst, row, sign)
    np.maximum.at(best, row, sign)
    reflex = worst < 0
    n_reflex = 0
    reflex_faces = np.zeros(0, np.int64)
    if reflex.any():
        lo = np.minimum(he.src[i[reflex]], he.dst[i[reflex]])
        hi = np.maximum(he.src[i[reflex]], he.dst[i[reflex]])
        n_reflex = len(np.unique(lo * max(n, 1) + hi))
        reflex_faces = np.unique(np.concatenate([fi[reflex], fj[reflex]]))
        reasons.append(f"{n_reflex} reflex edges")
        bad_rows = np.flatnonzero(reflex[row] & (sign < 0))
        pb = plane[fi[row[bad_rows]]]
        dist = point_plane_distance(points[pb[:, 0]], points[pb[:, 1]], points[pb[:, 2]], points[far[row[bad_rows], col[bad_rows]]])
        mags["reflex"] = float(dist.max())
    sharp_mask = best > 0
    src_u, dst_u = he.src[i[sharp_mask]], he.dst[i[sharp_mask]]
    nn = max(n, 1)
    sharp_key = np.unique(np.minimum(src_u, dst_u) * nn + np.maximum(src_u, dst_u))
    sharp_edges = np.stack([sharp_key // nn, sharp_key % nn], axis=1).astype(np.int64)

    # The interior point strictly below every face.
    has_plane = np.flatnonzero(~no_plane)
    pa, pb, pc = points[plane[has_plane, 0]], points[plane[has_plane, 1]], points[plane[has_plane, 2]]
    center = None
    if interior is None:
        flipped = np.zeros(0, dtype=np.int64)
        reasons.append("no interior point: the surface's vertices are coplanar")
    else:
        below = orient3d_mean(pa, pb, pc, interior.rows) > 0
        flipped = has_plane[~below]
        if flipped.size:
            reasons.append(f"{flipped.size} faces with the interior point not strictly below")
            dist = point_plane_distance(pa[~below], pb[~below], pc[~below], interior.approx)
            mags["flipped"] = float(np.maximum(dist, 0.0).max())
        # The vertices' mean sits near the middle of round hulls: a larger inscribed ball
        # makes the containment shortcut settle more points.
        candidates = (points[np.unique(faces.indices)].mean(axis=0), interior.approx) if len(has_plane) else ()
        for candidate in candidates:
            if bool(np.all(orient3d(pa, pb, pc, candidate) > 0)):
                center = np.asarray(candidate, dtype=np.float64)
                break

    degree = None
    if closed and not reasons and interior is not None:
        rng = np.random.default_rng(seed)
        if center is not None:
            def side_of_ray(u, v, rng, _c=center):
                q = _c + rng.normal(size=3)
                return -orient3d(_c, u, v, q)  # > 0: q strictly on the inner side of the plane (o, u, v)
        else:
            def side_of_ray(u, v, rng, _i=interior):
                q = _i.approx + rng.normal(size=3)
                # orient3d(o, u, v, q) = -orient3d(u, v, q, o) (a 4-cycle of the rows).
                return orient3d_mean(u, v, q, _i.rows)
        degree = _degree(points, faces, side_of_ray, rng)
        if degree is not None and degree != 1:
            reasons.append(f"the surface wraps {degree} times around the interior point")

    return Convexity3D(
        ok=not reasons,
        plane=plane,
        degenerate=degenerate,
        reflex_faces=reflex_faces,
        n_reflex_edges=n_reflex,
        flipped=flipped,
        sharp_edges=sharp_edges,
        center=center,
        degree=degree,
        magnitudes=mags,
        reasons=reasons,
    )
