"""A brute-force hull oracle in exact rationals, written apart from the checker (which it judges).

Everything here is the definition, evaluated the slowest obvious way: every
coordinate becomes the ``Fraction`` of its double, every sign is the sign of
a rational expression, nothing is filtered, scaled or rounded.  It imports
nothing from :mod:`hullstress`.  Meant for inputs of a dozen points.

What "valid" means (the checker's verdict with ``qhull=False``: convexity,
containment and manifoldness all pass) for a full-dimensional input:

2D, a polygon ``poly`` of vertex indices:
  at least three vertices, no index twice, no coordinates twice; every input
  point on or left of every edge (so every edge lies on the hull's boundary,
  oriented counter-clockwise); twice its signed area equals twice the area of
  the true hull (so it walks around the boundary exactly once).

3D, faces (polygons of vertex indices):
  each face: at least three vertices, no index twice, vertex area vector
  ``N = sum v_i x v_i+1`` not zero, every vertex on the plane ``N.(x - v0) = 0``,
  every vertex of the face on or left of every edge of the face seen along
  ``N`` (a convex polygon walked once, vertices on its edges allowed);
  every input point on or below every face plane (``N.(p - v0) <= 0``);
  the faces form a combinatorial sphere: every directed edge once and its
  reverse once, faces edge-connected, every vertex's link one cycle,
  ``V - E + F = 2``; no two used vertices at equal coordinates; six times
  the enclosed volume equals six times the true hull's volume.  Then the
  surface is a closed cycle on the hull's boundary with every face outward,
  so it covers the boundary a constant number of times, and the volume makes
  that number one.  Faces meet edge to edge (a vertex inside another face's
  edge, a T-junction, breaks the edge pairing): docs/checker.md.

The true hull is brute force too: in 2D the points left of or on every
directed pair's line are walked by angle; in 3D every triple's plane with all
points on one side is a facet plane, and its points' 2D hull is its facet.
"""

from __future__ import annotations

from fractions import Fraction
from itertools import combinations

import numpy as np

Vec = tuple


def rationals(points) -> list[tuple[Fraction, ...]]:
    """Every coordinate as the exact value of its double."""
    return [tuple(Fraction(float(x)) for x in row) for row in np.asarray(points, dtype=np.float64)]


def _sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def _dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def _cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _orient2(a, b, c) -> Fraction:
    """Twice the signed area of (a, b, c): positive when c is left of a -> b."""
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])


def affine_rank(pts) -> int:
    """Exact affine rank by Gaussian elimination on rationals (-1 for no points)."""
    if not pts:
        return -1
    rows = [list(_sub(p, pts[0])) for p in pts[1:]]
    rank = 0
    for col in range(len(pts[0])):
        piv = next((i for i in range(rank, len(rows)) if rows[i][col] != 0), None)
        if piv is None:
            continue
        rows[rank], rows[piv] = rows[piv], rows[rank]
        for i in range(len(rows)):
            if i != rank and rows[i][col] != 0:
                f = rows[i][col] / rows[rank][col]
                rows[i] = [x - f * y for x, y in zip(rows[i], rows[rank])]
        rank += 1
    return rank


# --------------------------------------------------------------------------- the true hull


def hull_polygon_2d(pts: list) -> list[int]:
    """Indices of the extreme points of a full-rank 2D set, counter-clockwise, one index per coordinate.

    Brute force: a directed pair (i, j) is a hull edge when every point is on
    or left of i -> j and the points on its line lie between i and j.
    """
    distinct = {}
    for i, p in enumerate(pts):
        distinct.setdefault(p, i)
    idx = list(distinct.values())
    succ = {}
    for i in idx:
        for j in idx:
            if i == j:
                continue
            a, b = pts[i], pts[j]
            sides = [_orient2(a, b, pts[k]) for k in idx]
            if min(sides) < 0:
                continue
            on = [k for k, s in zip(idx, sides) if s == 0]
            # i and j must be the two ends of the points on the line.
            t = [_dot(_sub(pts[k], a), _sub(b, a)) for k in on]
            if min(t) == 0 and max(t) == _dot(_sub(b, a), _sub(b, a)):
                succ[i] = j
    start = min(succ)
    ring = [start]
    while succ[ring[-1]] != start:
        ring.append(succ[ring[-1]])
    return ring


def twice_area(pts: list, ring) -> Fraction:
    return sum((_orient2((Fraction(0), Fraction(0)), pts[a], pts[b]) for a, b in zip(ring, list(ring[1:]) + [ring[0]])),
               Fraction(0))


def hull_facets_3d(pts: list) -> list[list[int]]:
    """The facets of a full-rank 3D set as polygons of its extreme points, counter-clockwise from outside."""
    distinct = {}
    for i, p in enumerate(pts):
        distinct.setdefault(p, i)
    idx = list(distinct.values())
    planes = {}
    for i, j, k in combinations(idx, 3):
        n = _cross(_sub(pts[j], pts[i]), _sub(pts[k], pts[i]))
        if n == (0, 0, 0):
            continue
        s = [_dot(n, _sub(pts[q], pts[i])) for q in idx]
        if max(s) > 0 and min(s) < 0:
            continue
        if max(s) > 0:
            n = tuple(-x for x in n)
        scale = max(abs(x) for x in n)
        key = (tuple(x / scale for x in n), _dot(n, pts[i]) / scale)
        planes[key] = (n, [q for q, v in zip(idx, s) if v == 0])
    facets = []
    for n, on in planes.values():
        drop = max(range(3), key=lambda c: abs(n[c]))  # project along the largest normal component
        keep = [c for c in range(3) if c != drop]
        flat = {q: (pts[q][keep[0]], pts[q][keep[1]]) for q in on}
        sub = list(flat)
        ring = [sub[r] for r in hull_polygon_2d([flat[q] for q in sub])]
        face = [ring[0], ring[1], ring[2]]
        if _dot(_cross(_sub(pts[face[1]], pts[face[0]]), _sub(pts[face[2]], pts[face[0]])), n) < 0:
            ring = ring[::-1]
        facets.append(ring)
    return facets


def six_volume(pts: list, faces) -> Fraction:
    """Six times the signed volume enclosed by polygon faces (fan triangles against the origin)."""
    total = Fraction(0)
    for f in faces:
        for t in range(1, len(f) - 1):
            total += _dot(pts[f[0]], _cross(pts[f[t]], pts[f[t + 1]]))
    return total


def triangulated(facets: list[list[int]]) -> list[list[int]]:
    """Fan triangles of convex facets (a valid triangle-mesh answer)."""
    return [[f[0], f[t], f[t + 1]] for f in facets for t in range(1, len(f) - 1)]


# --------------------------------------------------------------------------- the verdict


def valid_2d(points, poly) -> bool:
    """Whether ``poly`` is a valid hull of full-rank 2D ``points`` (module docstring)."""
    pts = rationals(points)
    poly = [int(i) for i in poly]
    if len(poly) < 3 or len(set(poly)) != len(poly) or len({pts[i] for i in poly}) != len(poly):
        return False
    for a, b in zip(poly, poly[1:] + poly[:1]):
        if any(_orient2(pts[a], pts[b], p) < 0 for p in pts):
            return False
    return twice_area(pts, poly) == twice_area(pts, hull_polygon_2d(pts))


def _face_ok(pts: list, face: list[int]) -> tuple | None:
    """The face's area vector when it is a planar convex polygon walked once, else None."""
    if len(face) < 3 or len(set(face)) != len(face):
        return None
    v = [pts[i] for i in face]
    if len(set(v)) != len(v):
        return None
    n = (Fraction(0),) * 3
    for a, b in zip(v, v[1:] + v[:1]):
        n = tuple(x + y for x, y in zip(n, _cross(a, b)))
    if n == (0, 0, 0) or any(_dot(n, _sub(p, v[0])) != 0 for p in v):
        return None
    for a, b in zip(v, v[1:] + v[:1]):
        if any(_dot(_cross(_sub(b, a), _sub(p, a)), n) < 0 for p in v):
            return None
    return n


def _is_sphere(faces: list[list[int]]) -> bool:
    """Every directed edge once and its reverse once, one edge-connected piece, links single cycles, V - E + F = 2."""
    directed = {}
    for f, face in enumerate(faces):
        for a, b in zip(face, face[1:] + face[:1]):
            if (a, b) in directed:
                return False
            directed[(a, b)] = f
    if any((b, a) not in directed for a, b in directed):
        return False
    # Edge-connected.
    seen, todo = {0}, [0]
    while todo:
        f = todo.pop()
        face = faces[f]
        for a, b in zip(face, face[1:] + face[:1]):
            g = directed[(b, a)]
            if g not in seen:
                seen.add(g)
                todo.append(g)
    if len(seen) != len(faces):
        return False
    # Each vertex's link: the corners (previous, next) around it chain into one cycle.
    link = {}
    for face in faces:
        k = len(face)
        for t, v in enumerate(face):
            link.setdefault(v, {})[face[(t + 1) % k]] = face[t - 1]
    for v, nxt in link.items():
        start = next(iter(nxt))
        walk, cur = 1, nxt[start]
        while cur != start and walk <= len(nxt):
            cur = nxt.get(cur)
            if cur is None:
                return False
            walk += 1
        if walk != len(nxt):
            return False
    vertices = {v for face in faces for v in face}
    return len(vertices) - len(directed) // 2 + len(faces) == 2


def valid_3d(points, faces) -> bool:
    """Whether polygon ``faces`` are a valid hull of full-rank 3D ``points`` (module docstring)."""
    pts = rationals(points)
    faces = [[int(i) for i in f] for f in faces]
    if not faces:
        return False
    for face in faces:
        n = _face_ok(pts, face)
        if n is None or any(_dot(n, _sub(p, pts[face[0]])) > 0 for p in pts):
            return False
    if not _is_sphere(faces):
        return False
    used = {v for face in faces for v in face}
    if len({pts[v] for v in used}) != len(used):
        return False
    return six_volume(pts, faces) == six_volume(pts, hull_facets_3d(pts))


def valid(points, faces) -> bool:
    """:func:`valid_2d` or :func:`valid_3d` by the points' dimension."""
    return valid_2d(points, faces) if np.shape(points)[1] == 2 else valid_3d(points, faces)
