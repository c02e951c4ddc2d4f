"""``certificate.json``: exact, independently checkable witnesses of why an output is not the hull.

:func:`build_certificate` searches the output (faces counter-clockwise seen
from outside, in the indices of the points the algorithm was given) for
witnesses, each a handful of indices and an exact sign or ratio that
``verify.py`` (:mod:`hullstress.report.verify_certificate`) recomputes with
nothing but :mod:`fractions`:

==================  ============================================  ===================
kind                what it shows                                 failed check
==================  ============================================  ===================
outside             a point strictly outside a face (exact sign)  containment
reflex              an edge whose neighbour face's vertex lies    convexity
                    above the face (3D)
reflex-vertex       a clockwise turn of the polygon (2D)          convexity
non-planar          four vertices of one face not coplanar        convexity
non-convex          two turns of one face in opposite senses      convexity
zero-area           a face whose distinct vertices are collinear  convexity
signed-area/volume  the exact signed measure is not positive      convexity
repeated-vertex     a vertex twice in one face (polygon)          convexity
coincident          two vertices of one face at the same point    convexity, manifoldness
edge-count          an edge in a number of faces other than two   manifoldness
edge-direction      an edge used twice in the same direction      manifoldness
missing-extreme     an extreme point (a strictly separating       qhull_agreement
                    direction) that is not an output vertex
not-extreme         a vertex that is a convex combination of      extreme_only
                    other points (rational weights)
face-size           a face that is not a triangle                 face_shape
flat                a normal every point is orthogonal to         flat_input
backtrack           a collinear walk turning back at a point      convexity
                    strictly inside the hull segment
==================  ============================================  ===================

Numbers are exact: coordinates and directions as ``float.hex`` strings when
they are doubles, other rationals as ``"p/q"``.  The search is bounded (a few
witnesses per kind, chunked scans) so that a large unshrunk case costs no more
than the checker did.  Checks with no witness found are listed under
``unwitnessed``; calls that ended in an error, timeout or crash have no
geometric certificate and say so (``geometric: false``).
"""

from __future__ import annotations

from fractions import Fraction
from typing import Any

import numpy as np

from ..checker import orient2d, orient3d

__all__ = ["build_certificate", "no_certificate", "exact_text", "WITNESS_CHECKS", "FORMAT"]

FORMAT = "hullstress-certificate/1"
#: Which failed check each witness kind certifies.
WITNESS_CHECKS = {
    "outside": "containment", "reflex": "convexity", "reflex-vertex": "convexity", "non-planar": "convexity",
    "non-convex": "convexity", "signed-area": "convexity", "signed-volume": "convexity",
    "repeated-vertex": "convexity", "coincident": "convexity,manifoldness", "edge-count": "manifoldness", "edge-direction": "manifoldness",
    "missing-extreme": "qhull_agreement,containment", "not-extreme": "extreme_only", "face-size": "face_shape",
    "flat": "flat_input", "backtrack": "convexity", "zero-area": "convexity",
}
_PER_KIND = 3
#: (point, face) pairs held at once by a scan.
_CHUNK = 200_000

Vec = list[Fraction]


def exact_text(x: Fraction | float) -> str:
    """A double as ``float.hex``, any other rational as ``"p/q"`` (both read back exactly)."""
    x = Fraction(x)
    if x.denominator & (x.denominator - 1) == 0 and abs(x.numerator) < 2**53:
        # A dyadic rational with a 53-bit numerator is a double only inside the exponent range: an exact
        # area of 2**-1100 would round to 0.0 (and a huge one overflow), so the round trip decides.
        try:
            as_float = float(x)
        except OverflowError:
            as_float = None
        if as_float is not None and Fraction(as_float) == x:
            return as_float.hex()
    return f"{x.numerator}/{x.denominator}"


def _sub(a: Vec, b: Vec) -> Vec:
    return [x - y for x, y in zip(a, b)]


def _dot(a: Vec, b: Vec) -> Fraction:
    return sum((x * y for x, y in zip(a, b)), Fraction(0))


def _cross(a: Vec, b: Vec) -> Vec:
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def _orient(P: list[Vec], ids: list[int]) -> int:
    """Exact sign: 2D (b-a)x(c-a); 3D det(b-a, c-a, d-a) (positive: d above ccw triangle abc)."""
    a = P[ids[0]]
    if len(a) == 2:
        u, v = _sub(P[ids[1]], a), _sub(P[ids[2]], a)
        d = u[0] * v[1] - u[1] * v[0]
    else:
        d = _dot(_cross(_sub(P[ids[1]], a), _sub(P[ids[2]], a)), _sub(P[ids[3]], a))
    return (d > 0) - (d < 0)


def no_certificate(status: str, reason: str) -> dict[str, Any]:
    """The certificate of a call that produced no hull: none, and why."""
    return {"format": FORMAT, "geometric": False, "status": status, "witnesses": [],
            "note": f"the call ended in {status} ({reason}): the {status} is its own evidence (see bug-report.md); "
                    "there is no output to certify"}


def _cyclic_edges(face: list[int]) -> list[tuple[int, int]]:
    return [(face[i], face[(i + 1) % len(face)]) for i in range(len(face))]


# ---- 2D -------------------------------------------------------------------------------------------

def _witnesses_2d(P: list[Vec], pts: np.ndarray, poly: list[int], hints: list[int]) -> list[dict[str, Any]]:
    out: list[dict[str, Any]] = []
    k = len(poly)
    seen: dict[int, int] = {}
    for pos, v in enumerate(poly):
        if v in seen and _count(out, "repeated-vertex") < _PER_KIND:
            out.append({"kind": "repeated-vertex", "vertex": v, "positions": [seen[v], pos]})
        seen.setdefault(v, pos)
    if k >= 3:
        area = _signed_area(P, poly)
        spanning = _spanning(P, 2) if area == 0 else None
        if area < 0 or spanning:
            out.append({"kind": "signed-area", "value": exact_text(area), **({"spanning": spanning} if spanning else {})})
        idx = np.asarray(poly)
        turns = orient2d(pts[idx], pts[np.roll(idx, -1)], pts[np.roll(idx, -2)])
        for i in np.flatnonzero(turns < 0)[:_PER_KIND]:
            a, b, c = poly[i], poly[(i + 1) % k], poly[(i + 2) % k]
            if _orient(P, [a, b, c]) < 0:
                out.append({"kind": "reflex-vertex", "vertices": [a, b, c], "orient": -1})
    if k >= 2:
        edges = np.asarray(_cyclic_edges(poly))
        found = 0
        for q in _scan_order(hints, len(P)):
            s = orient2d(pts[edges[:, 0]], pts[edges[:, 1]], np.repeat(pts[q:q + 1], len(edges), axis=0))
            for e in np.flatnonzero(s < 0)[:1]:
                a, b = int(edges[e, 0]), int(edges[e, 1])
                if _orient(P, [a, b, q]) < 0:
                    out.append({"kind": "outside", "point": q, "face": 0, "triangle": [a, b], "orient": -1})
                    found += 1
            if found >= _PER_KIND:
                break
    return out


def _signed_area(P: list[Vec], poly: list[int]) -> Fraction:
    o = P[min(poly)]  # the shoelace sum about a vertex: exact, and the same for every rotation
    total = Fraction(0)
    for u, v in _cyclic_edges(poly):
        b, c = _sub(P[u], o), _sub(P[v], o)
        total += (b[0] * c[1] - b[1] * c[0]) / 2
    return total


def _scan_order(hints: list[int], n: int, budget: int = 2000) -> list[int]:
    """The checker's offending points first, then the others, at most ``budget`` in all."""
    first = list(dict.fromkeys(int(h) for h in hints if 0 <= int(h) < n))
    taken = set(first)
    return (first + [i for i in range(min(n, budget + len(first))) if i not in taken])[:budget]


def _hull_2d(P: list[Vec]) -> list[int]:
    """Exact extreme points (counter-clockwise, one index per distinct point): Andrew's monotone chain."""
    order = sorted(range(len(P)), key=lambda i: (P[i][0], P[i][1], i))
    uniq: list[int] = []
    for i in order:
        if not uniq or P[uniq[-1]] != P[i]:
            uniq.append(i)
    if len(uniq) <= 2:
        return uniq

    def chain(seq: list[int]) -> list[int]:
        h: list[int] = []
        for i in seq:
            while len(h) >= 2 and _orient(P, [h[-2], h[-1], i]) <= 0:
                h.pop()
            h.append(i)
        return h

    lower, upper = chain(uniq), chain(uniq[::-1])
    return lower[:-1] + upper[:-1]


def _separating_2d(P: list[Vec], hull: list[int], j: int) -> Vec:
    """A direction in which hull vertex ``hull[j]`` is strictly the highest point."""
    p = P[hull[j]]
    if len(hull) == 2:
        return _sub(p, P[hull[1 - j]])
    a, b = P[hull[j - 1]], P[hull[(j + 1) % len(hull)]]
    d1, d2 = _sub(p, a), _sub(b, p)
    return [d1[1] + d2[1], -d1[0] - d2[0]]  # the sum of both edges' outward normals


# ---- 3D -------------------------------------------------------------------------------------------

def _witnesses_3d(P: list[Vec], pts: np.ndarray, faces: list[list[int]], hints: list[int]) -> list[dict[str, Any]]:
    out: list[dict[str, Any]] = []
    use: dict[tuple[int, int], list[int]] = {}
    for f, face in enumerate(faces):
        for u, v in _cyclic_edges(face):
            use.setdefault((u, v), []).append(f)
        dup = [v for v in set(face) if face.count(v) > 1]
        if dup and _count(out, "repeated-vertex") < _PER_KIND:
            out.append({"kind": "repeated-vertex", "face": f, "vertex": dup[0]})
        if len(face) >= 3 and len({tuple(P[v]) for v in face}) == len(face) and _count(out, "zero-area") < _PER_KIND:
            d0 = _sub(P[face[1]], P[face[0]])
            if all(not any(_cross(d0, _sub(P[v], P[face[0]]))) for v in face[2:]):
                out.append({"kind": "zero-area", "face": f})
        if len(face) > 3 and _count(out, "non-planar") < _PER_KIND:
            for i in range(3, len(face)):
                s = _orient(P, [face[0], face[1], face[2], face[i]])
                if s:
                    out.append({"kind": "non-planar", "face": f, "vertices": [face[0], face[1], face[2], face[i]],
                                "orient": s})
                    break
        if len(face) >= 4 and _count(out, "non-convex") < _PER_KIND:
            w = _opposite_turns(P, face)
            if w is not None:
                out.append({"kind": "non-convex", "face": f, "turns": w})
    undirected: dict[tuple[int, int], set[int]] = {}
    for (u, v), fs in use.items():
        undirected.setdefault((min(u, v), max(u, v)), set()).update(fs)
        if len(fs) >= 2 and _count(out, "edge-direction") < _PER_KIND and u != v:
            out.append({"kind": "edge-direction", "edge": [u, v], "faces": sorted(fs)[:2]})
    for (u, v), fs in sorted(undirected.items()):
        if len(fs) != 2 and u != v and _count(out, "edge-count") < _PER_KIND:
            out.append({"kind": "edge-count", "edge": [u, v], "count": len(fs), "faces": sorted(fs)})
    for (u, v), fs in sorted(use.items()):
        if _count(out, "reflex") >= _PER_KIND:
            break
        back = use.get((v, u), [])
        if len(fs) != 1 or len(back) != 1:
            continue
        f, g = faces[fs[0]], faces[back[0]]
        x = f[(f.index(v) + 1) % len(f)]
        for w in g:
            if w not in (u, v, x) and _orient(P, [u, v, x, w]) > 0:
                out.append({"kind": "reflex", "faces": [fs[0], back[0]], "triangle": [u, v, x], "apex": w,
                            "orient": 1})
                break
    if faces and all(len(fs) == 1 and len(use.get((v, u), [])) == 1 for (u, v), fs in use.items()):
        vol = _signed_volume(P, faces)
        spanning = _spanning(P, 3) if vol == 0 else None
        if vol < 0 or spanning:
            out.append({"kind": "signed-volume", "value": exact_text(vol), **({"spanning": spanning} if spanning else {})})
    out += _outside_3d(P, pts, faces, hints)
    return out


def _spanning(P: list[Vec], dim: int) -> list[int] | None:
    """``dim + 1`` points of nonzero exact orientation (the input is full-dimensional), or None."""
    from ..checker import witness_simplex

    try:
        simplex = witness_simplex(np.asarray([[float(x) for x in p] for p in P]))
    except Exception:
        simplex = None
    if simplex is None or len(simplex) != dim + 1:
        return None
    ids = [int(i) for i in simplex]
    return ids if _orient(P, ids) != 0 else None


def _count(out: list[dict[str, Any]], kind: str) -> int:
    return sum(1 for w in out if w["kind"] == kind)


def _opposite_turns(P: list[Vec], face: list[int]) -> list[list[int]] | None:
    k = len(face)
    ref: tuple[list[int], Vec] | None = None
    for i in range(k):
        a, b, c = face[i], face[(i + 1) % k], face[(i + 2) % k]
        t = _cross(_sub(P[b], P[a]), _sub(P[c], P[b]))
        if ref is None:
            if any(t):
                ref = ([a, b, c], t)
        elif _dot(ref[1], t) < 0:
            return [ref[0], [a, b, c]]
    return None


def _signed_volume(P: list[Vec], faces: list[list[int]]) -> Fraction:
    o = P[min(v for f in faces for v in f)]
    total = Fraction(0)
    for f in faces:
        for i in range(1, len(f) - 1):
            total += _dot(_cross(_sub(P[f[0]], o), _sub(P[f[i]], o)), _sub(P[f[i + 1]], o)) / 6
    return total


def _outside_3d(P: list[Vec], pts: np.ndarray, faces: list[list[int]], hints: list[int]) -> list[dict[str, Any]]:
    tri, face_of = [], []
    for f, face in enumerate(faces):
        for i in range(1, len(face) - 1):
            tri.append((face[0], face[i], face[i + 1]))
            face_of.append(f)
    if not tri:
        return []
    t = np.asarray(tri)
    a, b, c = pts[t[:, 0]], pts[t[:, 1]], pts[t[:, 2]]
    out: list[dict[str, Any]] = []
    for q in _scan_order(hints, len(P)):
        s = orient3d(a, b, c, np.repeat(pts[q:q + 1], len(t), axis=0))  # the checker's sign: negative is above
        for j in np.flatnonzero(s < 0)[:1]:
            ids = [int(x) for x in t[j]]
            if q not in ids and _orient(P, ids + [q]) > 0:
                out.append({"kind": "outside", "point": q, "face": int(face_of[j]), "triangle": ids, "orient": 1})
        if len(out) >= _PER_KIND:
            break
    return out


def _extreme_3d(pts: np.ndarray, P: list[Vec]) -> tuple[list[int], list[list[int]]]:
    """Candidate extreme points and outward triangles from Qhull, each triangle's orientation fixed exactly."""
    from scipy.spatial import ConvexHull

    try:
        hull = ConvexHull(pts)
    except Exception:  # flat or too few points: no 3D hull to separate with
        return [], []
    centre = [sum((P[v][k] for v in hull.vertices), Fraction(0)) / len(hull.vertices) for k in range(3)]
    tris = []
    for s in hull.simplices.tolist():
        a, b, c = P[s[0]], P[s[1]], P[s[2]]
        side = _dot(_cross(_sub(b, a), _sub(c, a)), _sub(centre, a))
        tris.append(s if side < 0 else [s[0], s[2], s[1]])
    return [int(v) for v in hull.vertices], tris


def _normal(P: list[Vec], t: list[int]) -> Vec:
    return _cross(_sub(P[t[1]], P[t[0]]), _sub(P[t[2]], P[t[0]]))


def _separates(P: list[Vec], p: int, c: Vec) -> bool:
    top = _dot(c, P[p])
    return any(c) and all(_dot(c, r) < top for r in P if r != P[p])


def _flat_axes(P: list[Vec]) -> tuple[int, int] | None:
    """Two coordinate axes onto which flat 3D points project one-to-one (None: not flat, or one point)."""
    base = P[0]
    diffs = [_sub(p, base) for p in P if p != base]
    if not diffs:
        return None
    normal = next((n for d in diffs[1:] for n in [_cross(diffs[0], d)] if any(n)), None)
    if normal is not None:
        if any(_dot(normal, d) for d in diffs):
            return None  # full-dimensional
        drop = max(range(3), key=lambda i: abs(normal[i]))  # the plane is a graph over the other two axes
    else:
        keep = max(range(3), key=lambda i: abs(diffs[0][i]))  # a line: any plane holding its main axis
        drop = (keep + 1) % 3
    a, b = [i for i in range(3) if i != drop]
    return a, b


def _missing_extreme(P: list[Vec], pts: np.ndarray, out_vertices: set[int], dim: int,
                     hull2: list[int] | None, tris3: list[list[int]], cand3: list[int]) -> list[dict[str, Any]]:
    used = {tuple(P[v]) for v in out_vertices}
    found: list[dict[str, Any]] = []
    flat = _flat_axes(P) if dim == 3 else None
    if flat is not None:
        # Flat 3D input: its extreme points are those of an exact projection; a direction in the
        # projection plane, with zero on the dropped axis, separates them in 3D as well.
        a, b = flat
        P2 = [[p[a], p[b]] for p in P]
        hull_flat = _hull_2d(P2)
    cands = hull2 if dim == 2 else (hull_flat if flat is not None else cand3)
    for j, p in enumerate(cands or []):
        if tuple(P[p]) in used:
            continue
        if flat is not None:
            c2 = _separating_2d(P2, hull_flat, j)
            c = [Fraction(0)] * 3
            c[a], c[b] = c2[0], c2[1]
        elif dim == 2:
            c = _separating_2d(P, hull2, j)
        else:
            c = [Fraction(0)] * 3
            for t in tris3:
                if p in t:
                    c = [x + y for x, y in zip(c, _normal(P, t))]
        if _separates(P, p, c):
            found.append({"kind": "missing-extreme", "point": p, "direction": [exact_text(x) for x in c]})
        if len(found) >= _PER_KIND:
            break
    return found


def _barycentric(P: list[Vec], v: int, ids: list[int]) -> list[Fraction] | None:
    """Weights of ``P[v]`` in the segment or triangle ``ids`` (all >= 0, sum 1), or None."""
    x = P[v]
    if len(ids) == 2:
        a, b = P[ids[0]], P[ids[1]]
        d = _sub(b, a)
        k = next((i for i, di in enumerate(d) if di), None)
        if k is None:
            return None
        t = (x[k] - a[k]) / d[k]
        if [ai + t * di for ai, di in zip(a, d)] != x or not 0 <= t <= 1:
            return None
        return [1 - t, t]
    a, b, c = (P[i] for i in ids)
    u, w, r = _sub(b, a), _sub(c, a), _sub(x, a)
    n = _cross(u + [Fraction(0)] * (3 - len(u)), w + [Fraction(0)] * (3 - len(w)))
    k = max(range(3), key=lambda i: abs(n[i]))
    if n[k] == 0:
        return None
    i, j = [m for m in range(3) if m != k][:2] if len(u) == 3 else (0, 1)
    det = u[i] * w[j] - u[j] * w[i]
    s = (r[i] * w[j] - r[j] * w[i]) / det
    t = (u[i] * r[j] - u[j] * r[i]) / det
    lam = [1 - s - t, s, t]
    if min(lam) < 0 or [a[m] + s * u[m] + t * w[m] for m in range(len(a))] != x:
        return None
    return lam


def _not_extreme(P: list[Vec], out_vertices: set[int], dim: int, hull2: list[int] | None,
                 tris3: list[list[int]], cand3: list[int]) -> list[dict[str, Any]]:
    extreme = hull2 if dim == 2 else cand3
    if not extreme:
        return []
    coords = {tuple(P[e]) for e in extreme}
    pieces: list[list[int]] = []
    if dim == 2:
        m = len(extreme)
        pieces = [[extreme[i], extreme[(i + 1) % m]] for i in range(m if m > 2 else 1)]
        pieces += [[extreme[0], extreme[i], extreme[i + 1]] for i in range(1, m - 1)]
    else:
        pieces = tris3 + [[t[0], t[1]] for t in tris3]
    found: list[dict[str, Any]] = []
    for v in sorted(out_vertices):
        if tuple(P[v]) in coords:
            continue
        for ids in pieces:
            lam = _barycentric(P, v, ids)
            if lam is not None and all(x < 1 for x in lam):
                found.append({"kind": "not-extreme", "vertex": v,
                              "combination": [[i, exact_text(x)] for i, x in zip(ids, lam)]})
                break
        if len(found) >= _PER_KIND:
            break
    return found


def _coincident(faces: list[list[int]], P: list[Vec], dim: int) -> list[dict[str, Any]]:
    """Two distinct indices of one face at the same coordinates: a zero-length edge or a pinched face."""
    found: list[dict[str, Any]] = []
    for f, face in enumerate(faces):
        first: dict[tuple[Fraction, ...], int] = {}
        for v in face:
            u = first.setdefault(tuple(P[v]), v)
            if u != v:
                found.append({"kind": "coincident", "face": f, "vertices": [u, v]})
                break
        if len(found) >= _PER_KIND:
            break
    return found


def _backtracks(P: list[Vec], poly: list[int], ends: list[int]) -> list[dict[str, Any]]:
    """Collinear input: the walk turns back at a vertex strictly inside the hull segment ``ends``."""
    found: list[dict[str, Any]] = []
    k = len(poly)
    for i in range(k if k >= 3 else 0):
        a, b, c = poly[i - 1], poly[i], poly[(i + 1) % k]
        if _orient(P, [a, b, c]) == 0 and _dot(_sub(P[b], P[a]), _sub(P[c], P[b])) < 0:
            lam = _barycentric(P, b, ends)
            if lam is not None and all(x < 1 for x in lam):
                found.append({"kind": "backtrack", "vertices": [a, b, c],
                              "combination": [[e, exact_text(x)] for e, x in zip(ends, lam)]})
                break
    return found


def _flat(P: list[Vec], dim: int) -> list[dict[str, Any]]:
    """A nonzero normal every point is orthogonal to (through point 0), when the points are flat."""
    base = P[0]
    diffs = [_sub(p, base) for p in P if p != base]
    if dim == 2:
        d = diffs[0] if diffs else [Fraction(1), Fraction(0)]
        n = [-d[1], d[0]]
    else:
        n = [Fraction(0)] * 3
        for i in range(len(diffs)):
            n = _cross(diffs[0], diffs[i])
            if any(n):
                break
        if not any(n):
            d = diffs[0] if diffs else [Fraction(1), Fraction(0), Fraction(0)]
            n = _cross(d, [Fraction(1), Fraction(0), Fraction(0)]) if (d[1] or d[2]) else [Fraction(0), Fraction(1), Fraction(0)]
    if any(n) and all(_dot(n, dd) == 0 for dd in diffs):
        return [{"kind": "flat", "normal": [exact_text(x) for x in n], "through": 0}]
    return []


def build_certificate(points: np.ndarray, faces: Any, *, dim: int, failed_checks: list[str],
                      hints: list[int] = (), points_file: str, faces_file: str,
                      **about: Any) -> dict[str, Any]:
    """Witnesses of every failed check that can be found for ``faces`` as a hull of ``points``.

    Parameters
    ----------
    points : ndarray of shape (n, dim)
        The points the algorithm was given (finite).
    faces : list
        The output as judged: a 2D polygon (list of int) or 3D faces (list of lists),
        counter-clockwise seen from outside.
    dim : {2, 3}
    failed_checks : list of str
        The row's failed checks (``containment``, ``extreme_only``, ...).
    hints : sequence of int
        Points the checker reported (scanned first).
    points_file, faces_file : str
        The folder's files holding ``points`` and ``faces`` (the verifier compares).
    **about
        Extra JSON fields (algorithm, contract, status).

    Returns
    -------
    dict
        JSON-ready; ``witnesses`` may be empty when no search succeeded.
    """
    pts = np.ascontiguousarray(points, dtype=np.float64)
    P = [[Fraction(float(x)) for x in row] for row in pts.tolist()]
    if dim == 2:
        poly = [int(v) for v in faces]
        out_vertices = set(poly)
        witnesses = _witnesses_2d(P, pts, poly, list(hints))
    else:
        face_list = [[int(v) for v in f] for f in faces]
        out_vertices = {v for f in face_list for v in f}
        witnesses = _witnesses_3d(P, pts, face_list, list(hints))
    witnesses += _coincident([poly] if dim == 2 else face_list, P, dim)
    want = set(failed_checks)
    hull2 = _hull_2d(P) if dim == 2 else None
    # Qhull proposes the 3D extreme points; each separating direction is then checked exactly.
    cand3, tris3 = _extreme_3d(pts, P) if dim == 3 and _flat_axes(P) is None else ([], [])
    witnesses += _missing_extreme(P, pts, out_vertices, dim, hull2, tris3, cand3)
    if dim == 2 and hull2 is not None and len(hull2) == 2:
        witnesses += _backtracks(P, poly, hull2)
    if "extreme_only" in want:
        witnesses += _not_extreme(P, out_vertices, dim, hull2, tris3, cand3)
    if "face_shape" in want and dim == 3:
        witnesses += [{"kind": "face-size", "face": f, "size": len(face)}
                      for f, face in enumerate(face_list) if len(face) != 3][:_PER_KIND]
    if "flat_input" in want:
        witnesses += _flat(P, dim)
    covered = {c for w in witnesses for c in WITNESS_CHECKS[w["kind"]].split(",")}
    return {"format": FORMAT, "geometric": True, **about, "dim": dim, "failed_checks": list(failed_checks),
            "points_file": points_file, "faces_file": faces_file,
            "points": [[x.hex() for x in row] for row in pts.tolist()],
            "faces": faces, "witnesses": witnesses,
            "unwitnessed": [c for c in failed_checks if c not in covered],
            "convention": "faces counter-clockwise seen from outside (2D: one counter-clockwise polygon); "
                          "orient > 0 means above the face's plane (3D), orient < 0 right of the edge (2D)"}
