"""Manifoldness of a 3D surface: docs/design.md's closed, oriented, genus-0 condition.

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

from ..contract import FaceSet
from ._geometry import triangle_array
from ._unique import unique_ints
from .measure import Measure, surface_measure

__all__ = ["HalfEdges", "Topology", "half_edges", "check_topology", "components"]


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
    count : ndarray of shape (h,), int64
        How many half-edges run ``src -> dst`` (1 on a consistently oriented surface).
    paired : bool
        Every half-edge has a unique twin and no directed edge repeats: edges pair up exactly.
    """

    src: np.ndarray
    dst: np.ndarray
    face: np.ndarray
    next: np.ndarray
    twin: np.ndarray
    count: np.ndarray
    paired: bool


_NEXT3 = np.array([1, 2, 0])


def half_edges(faces: FaceSet, n_points: int) -> HalfEdges:
    """Build the half-edge arrays of ``faces`` (twins matched by exact vertex indices)."""
    h = len(faces.indices)
    tri = triangle_array(faces)
    if tri is not None:
        face = np.arange(h, dtype=np.int64) // 3
        nxt = face * 3 + _NEXT3[np.arange(h) % 3]
        dst = tri[:, _NEXT3].ravel()
    else:
        sizes = faces.sizes
        face = np.repeat(np.arange(faces.n_faces, dtype=np.int64), sizes)
        start = faces.offsets[:-1][face]
        pos = np.arange(h, dtype=np.int64) - start
        nxt = start + (pos + 1) % np.maximum(sizes[face], 1)
        dst = faces.indices[nxt]
    src = faces.indices
    n = max(int(n_points), 1)
    key = src * n + dst
    order = np.argsort(key, kind="stable")
    sorted_key = key[order]
    rev = dst * n + src
    lo = np.searchsorted(sorted_key, rev, side="left")
    twin = np.full(h, -1, dtype=np.int64)
    if not h or not np.any(sorted_key[1:] == sorted_key[:-1]):
        # No directed edge repeats (the common case): a reverse edge is there or not.
        count = np.ones(h, dtype=np.int64)
        found = sorted_key[np.minimum(lo, h - 1)] == rev if h else np.zeros(0, dtype=bool)
        twin[found] = order[lo[found]]
        return HalfEdges(src, dst, face, nxt, twin, count, bool(found.all()))
    hi = np.searchsorted(sorted_key, rev, side="right")
    unique_rev = hi - lo == 1
    twin[unique_rev] = order[lo[unique_rev]]
    count = np.searchsorted(sorted_key, key, side="right") - np.searchsorted(sorted_key, key, side="left")
    return HalfEdges(src, dst, face, nxt, twin, count, False)


def components(n: int, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Connected components of the undirected graph on ``0..n-1`` with edges ``(u[i], v[i])``.

    Union-find in whole-array steps: every root is hooked under the smallest
    root across its edges, then paths are shortcut until every node points
    at its root; repeated until no edge joins two roots.  A few rounds for the
    graphs met here, each a handful of numpy calls (no per-call set-up of a
    sparse matrix).

    Returns
    -------
    ndarray of shape (n,), int64
        Each node's label: the smallest node of its component.

    Examples
    --------
    >>> components(5, np.array([3, 1]), np.array([4, 0])).tolist()
    [0, 0, 2, 3, 3]
    """
    label = np.arange(n, dtype=np.int64)
    if not len(u):
        return label
    while True:
        lu, lv = label[u], label[v]
        if np.array_equal(lu, lv):
            return label
        low = np.minimum(lu, lv)
        np.minimum.at(label, lu, low)
        np.minimum.at(label, lv, low)
        while True:
            up = label[label]
            if np.array_equal(up, label):
                break
            label = up


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
    t = triangle_array(faces)
    if t is not None:
        return np.flatnonzero((t[:, 0] == t[:, 1]) | (t[:, 1] == t[:, 2]) | (t[:, 0] == t[:, 2]))
    face = np.repeat(np.arange(faces.n_faces, dtype=np.int64), faces.sizes)
    order = np.lexsort((faces.indices, face))
    f_sorted, v_sorted = face[order], faces.indices[order]
    dup = (f_sorted[1:] == f_sorted[:-1]) & (v_sorted[1:] == v_sorted[:-1])
    return unique_ints(f_sorted[1:][dup])


def _repeated_faces(faces: FaceSet, n_points: int, triangles: bool) -> np.ndarray:
    """Faces whose vertex set equals another face's (all copies are reported)."""
    if faces.n_faces == 0:
        return np.zeros(0, dtype=np.int64)
    if triangles:
        keys = np.sort(triangle_array(faces), axis=1)
        n = max(n_points, 1)
        if n < 2**20:  # one int64 per sorted triple
            key = (keys[:, 0] * n + keys[:, 1]) * n + keys[:, 2]
            _, inv, counts = np.unique(key, return_inverse=True, return_counts=True)
            return np.flatnonzero(counts[inv.ravel()] > 1)
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


def _link_cycles(he: HalfEdges) -> np.ndarray:
    """Vertices whose corners fall into more than one orbit of the turn-around permutation.

    The corner of half-edge ``i`` sits at ``src[i]``.  Turning around that
    vertex: the twin of ``i`` runs ``dst -> src`` in the next face, whose
    following half-edge starts again at ``src[i]``.
    """
    h = len(he.src)
    idx = np.flatnonzero(he.twin >= 0)
    label = components(h, idx, he.next[he.twin[idx]])
    pairs = unique_ints(he.src * (h + 1) + label)
    verts, counts = np.unique(pairs // (h + 1), return_counts=True)
    return verts[counts > 1]


def _closed_triangle_mesh(
    points: np.ndarray, faces: FaceSet, he: HalfEdges, measure: Measure | None
) -> Topology | None:
    """The verdict on a triangle mesh whose edges pair up exactly, when it is a sphere; else None.

    With every directed edge once and its reverse once (``he.paired``), no
    triangle repeating a vertex, one connected piece of more than two faces
    and V - E + F = 2, the general checks below cannot fail except for the
    orientation, so they are skipped: two faces on the same three vertices
    pair all their edges with each other (a piece of two faces), and every
    vertex's link is a single cycle, because the surface glued from the faces
    is a connected closed orientable surface, whose Euler characteristic
    ``(link cycles) - E + F`` is at most 2 while there are at least V link
    cycles.
    """
    t = triangle_array(faces)
    if np.any((t[:, 0] == t[:, 1]) | (t[:, 1] == t[:, 2]) | (t[:, 0] == t[:, 2])):
        return None
    half = np.flatnonzero(he.src < he.dst)  # one half-edge per edge
    label = components(faces.n_faces, he.face[half], he.face[he.twin[half]])
    if np.any(label != 0):
        return None
    n_edges = len(half)
    if len(unique_ints(t)) - n_edges + faces.n_faces != 2:
        return None
    sign = (measure if measure is not None else surface_measure(points, faces)).sign
    reasons = [] if sign > 0 else ["inward orientation (signed volume negative)" if sign < 0 else "zero signed volume"]
    empty = np.zeros(0, np.int64)
    return Topology(not reasons, empty, empty, reasons, n_edges)


def check_topology(
    points: np.ndarray, faces: FaceSet, *, he: HalfEdges | None = None, measure: Measure | None = None
) -> Topology:
    """Check docs/design.md's manifoldness for a 3D surface.

    Parameters
    ----------
    points : ndarray of shape (n, 3), float64
    faces : FaceSet
        Validated faces (indices in range).
    he : HalfEdges or None
        The surface's half-edges, when the caller has them already.
    measure : Measure or None
        The surface's signed volume (:func:`~.measure.surface_measure`), when
        the caller has it already; its exact sign decides the orientation.

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
    if he is None:
        he = half_edges(faces, n)
    triangles = triangle_array(faces) is not None
    if triangles and he.paired and faces.n_faces > 2:
        quick = _closed_triangle_mesh(points, faces, he, measure)
        if quick is not None:
            return quick

    rep_v = _repeated_vertex_faces(faces)
    if rep_v.size:
        reasons.append(f"{rep_v.size} faces repeat a vertex")
        bad_faces.append(rep_v)

    multi = he.count > 1
    if multi.any():
        reasons.append(f"{int(multi.sum())} half-edges occur more than once in the same direction")
        bad_faces.append(he.face[multi])
        bad_vertices.append(np.concatenate([he.src[multi], he.dst[multi]]))
    lonely = (he.twin < 0) & ~multi
    if lonely.any():
        reasons.append(f"{int(lonely.sum())} edges without an opposite half-edge (border or same-direction neighbour)")
        bad_faces.append(he.face[lonely])
        bad_vertices.append(np.concatenate([he.src[lonely], he.dst[lonely]]))

    rep_f = _repeated_faces(faces, n, triangles)
    if rep_f.size:
        reasons.append(f"{rep_f.size} repeated faces")
        bad_faces.append(rep_f)

    link_bad = _link_cycles(he)
    if link_bad.size:
        reasons.append(f"{link_bad.size} vertices whose link is not a single cycle")
        bad_vertices.append(link_bad)

    if he.paired:
        n_edges = len(he.src) // 2
    else:
        n_edges = len(unique_ints(np.minimum(he.src, he.dst) * max(n, 1) + np.maximum(he.src, he.dst)))
    paired = np.flatnonzero(he.twin >= 0)
    face_label = components(faces.n_faces, he.face[paired], he.face[he.twin[paired]])
    n_pieces = int(np.count_nonzero(face_label == np.arange(faces.n_faces)))
    if n_pieces != 1:
        reasons.append(f"{n_pieces} connected pieces")
    n_vertices = len(unique_ints(faces.indices))
    euler = n_vertices - n_edges + faces.n_faces
    if euler != 2:
        reasons.append(f"Euler characteristic {euler}, expected 2")

    if not reasons:
        sign = (measure if measure is not None else surface_measure(points, faces)).sign
        if sign <= 0:
            reasons.append("inward orientation (signed volume negative)" if sign < 0 else "zero signed volume")

    def cat(parts: list[np.ndarray]) -> np.ndarray:
        return unique_ints(np.concatenate(parts)).astype(np.int64) if parts else np.zeros(0, np.int64)

    return Topology(not reasons, cat(bad_faces), cat(bad_vertices), reasons, n_edges)
