"""Manifoldness of a 3D surface: DESIGN.md's closed, oriented, genus-0 condition.

A surface passes when

* every face is a cycle of distinct vertex indices;
* every directed edge ``u -> v`` occurs in exactly one face and its reverse
  ``v -> u`` in exactly one other (every undirected edge in exactly two faces,
  in opposite directions);
* no two faces have the same vertex set;
* every vertex's link is a single cycle (the corners around it form one orbit
  of the "turn around the vertex" permutation);
* the faces form one connected piece with Euler characteristic V - E + F = 2;
* the signed volume is positive (exactly): the orientation is outward.

Everything is vectorised on half-edges (one per face corner) except the
repeated-face test for non-triangular faces.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from ..contract import FaceSet
from .predicates import orient3d_sum_sign

__all__ = ["HalfEdges", "Topology", "half_edges", "check_topology"]


@dataclass(frozen=True)
class HalfEdges:
    """One half-edge per face corner, in :class:`FaceSet` index order.

    Attributes
    ----------
    src, dst, face, next : ndarray of shape (h,), int64
        Half-edge ``i`` runs ``src[i] -> dst[i]`` in face ``face[i]``;
        ``next[i]`` is the following half-edge of the same face.
    twin : ndarray of shape (h,), int64
        The unique half-edge ``dst -> src``, or -1 when there is none or it is
        not unique.
    """

    src: np.ndarray
    dst: np.ndarray
    face: np.ndarray
    next: np.ndarray
    twin: np.ndarray


def half_edges(faces: FaceSet, n_points: int) -> HalfEdges:
    """Build the half-edge arrays of ``faces`` (twins matched by exact vertex indices)."""
    sizes = faces.sizes
    h = len(faces.indices)
    face = np.repeat(np.arange(faces.n_faces, dtype=np.int64), sizes)
    start = faces.offsets[:-1][face]
    pos = np.arange(h, dtype=np.int64) - start
    nxt = start + (pos + 1) % np.maximum(sizes[face], 1)
    src = faces.indices
    dst = faces.indices[nxt]
    n = max(int(n_points), 1)
    key = src * n + dst
    order = np.argsort(key, kind="stable")
    sorted_key = key[order]
    rev = dst * n + src
    lo = np.searchsorted(sorted_key, rev, side="left")
    hi = np.searchsorted(sorted_key, rev, side="right")
    twin = np.full(h, -1, dtype=np.int64)
    unique_rev = hi - lo == 1
    twin[unique_rev] = order[lo[unique_rev]]
    return HalfEdges(src, dst, face, nxt, twin)


@dataclass
class Topology:
    """What the manifoldness check found.

    Attributes
    ----------
    ok : bool
    bad_faces, bad_vertices : ndarray of int64
        Faces and vertices where the condition breaks (sorted, unique).
    reasons : list of str
        Short descriptions of each failed condition.
    n_edges : int
        Number of undirected edges.
    """

    ok: bool
    bad_faces: np.ndarray
    bad_vertices: np.ndarray
    reasons: list[str] = field(default_factory=list)
    n_edges: int = 0


def _repeated_vertex_faces(faces: FaceSet) -> np.ndarray:
    face = np.repeat(np.arange(faces.n_faces, dtype=np.int64), faces.sizes)
    order = np.lexsort((faces.indices, face))
    f_sorted, v_sorted = face[order], faces.indices[order]
    dup = (f_sorted[1:] == f_sorted[:-1]) & (v_sorted[1:] == v_sorted[:-1])
    return np.unique(f_sorted[1:][dup])


def _repeated_faces(faces: FaceSet) -> np.ndarray:
    """Faces whose vertex set equals another face's (all copies are reported)."""
    if faces.n_faces == 0:
        return np.zeros(0, dtype=np.int64)
    if faces.is_triangles:
        keys = np.sort(faces.triangles(), axis=1)
        order = np.lexsort((keys[:, 2], keys[:, 1], keys[:, 0]))
        same = np.all(keys[order][1:] == keys[order][:-1], axis=1)
        dup = np.zeros(len(keys), dtype=bool)
        dup[order[1:][same]] = True
        dup[order[:-1][same]] = True
        return np.flatnonzero(dup)
    seen: dict[tuple[int, ...], list[int]] = {}
    for i in range(faces.n_faces):
        seen.setdefault(tuple(sorted(faces.face(i).tolist())), []).append(i)
    return np.array(sorted(i for group in seen.values() if len(group) > 1 for i in group), dtype=np.int64)


def _link_cycles(he: HalfEdges, n_points: int) -> np.ndarray:
    """Vertices whose corners fall into more than one orbit of the turn-around permutation.

    The corner of half-edge ``i`` sits at ``src[i]``.  Turning around that
    vertex: the twin of ``i`` runs ``dst -> src`` in the next face, whose
    following half-edge starts again at ``src[i]``.
    """
    h = len(he.src)
    ok = he.twin >= 0
    idx = np.flatnonzero(ok)
    succ = he.next[he.twin[idx]]
    graph = coo_matrix((np.ones(len(idx), dtype=np.int8), (idx, succ)), shape=(h, h))
    _, label = connected_components(graph, directed=True, connection="weak")
    pairs = np.unique(he.src * (h + 1) + label)
    verts, counts = np.unique(pairs // (h + 1), return_counts=True)
    return verts[counts > 1]


def check_topology(points: np.ndarray, faces: FaceSet) -> Topology:
    """Check DESIGN.md's manifoldness for a 3D surface.

    Parameters
    ----------
    points : ndarray of shape (n, 3), float64
    faces : FaceSet
        Validated faces (indices in range).

    Returns
    -------
    Topology

    Examples
    --------
    >>> p = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    >>> tet = FaceSet.from_triangles([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    >>> check_topology(p, tet).ok
    True
    >>> check_topology(p, FaceSet.from_triangles([[0, 1, 2], [0, 2, 1]])).reasons
    ['2 repeated faces']
    """
    n = len(points)
    reasons: list[str] = []
    bad_faces: list[np.ndarray] = []
    bad_vertices: list[np.ndarray] = []
    if faces.n_faces == 0:
        return Topology(False, np.zeros(0, np.int64), np.zeros(0, np.int64), ["no faces"], 0)
    he = half_edges(faces, n)

    rep_v = _repeated_vertex_faces(faces)
    if rep_v.size:
        reasons.append(f"{rep_v.size} faces repeat a vertex")
        bad_faces.append(rep_v)

    key = he.src * max(n, 1) + he.dst
    _, inv, counts = np.unique(key, return_inverse=True, return_counts=True)
    multi = counts[inv.ravel()] > 1
    if multi.any():
        reasons.append(f"{int(multi.sum())} half-edges occur more than once in the same direction")
        bad_faces.append(he.face[multi])
        bad_vertices.append(np.concatenate([he.src[multi], he.dst[multi]]))
    lonely = (he.twin < 0) & ~multi
    if lonely.any():
        reasons.append(f"{int(lonely.sum())} edges without an opposite half-edge (border or same-direction neighbour)")
        bad_faces.append(he.face[lonely])
        bad_vertices.append(np.concatenate([he.src[lonely], he.dst[lonely]]))

    rep_f = _repeated_faces(faces)
    if rep_f.size:
        reasons.append(f"{rep_f.size} repeated faces")
        bad_faces.append(rep_f)

    link_bad = _link_cycles(he, n)
    if link_bad.size:
        reasons.append(f"{link_bad.size} vertices whose link is not a single cycle")
        bad_vertices.append(link_bad)

    n_edges = len(np.unique(np.minimum(he.src, he.dst) * max(n, 1) + np.maximum(he.src, he.dst)))
    paired = he.twin >= 0
    graph = coo_matrix(
        (np.ones(int(paired.sum()), dtype=np.int8), (he.face[paired], he.face[he.twin[paired]])),
        shape=(faces.n_faces, faces.n_faces),
    )
    n_pieces, _ = connected_components(graph, directed=False)
    if n_pieces != 1:
        reasons.append(f"{n_pieces} connected pieces")
    n_vertices = len(np.unique(faces.indices))
    euler = n_vertices - n_edges + faces.n_faces
    if euler != 2:
        reasons.append(f"Euler characteristic {euler}, expected 2")

    if not reasons:
        tri, _ = faces.fan_triangles()
        ref = points[tri[0, 0]]
        sign = orient3d_sum_sign(points[tri[:, 0]], points[tri[:, 1]], points[tri[:, 2]], ref)
        if sign <= 0:
            reasons.append("inward orientation (signed volume negative)" if sign < 0 else "zero signed volume")

    def cat(parts: list[np.ndarray]) -> np.ndarray:
        return np.unique(np.concatenate(parts)).astype(np.int64) if parts else np.zeros(0, np.int64)

    return Topology(not reasons, cat(bad_faces), cat(bad_vertices), reasons, n_edges)
