"""Containment: no input point strictly outside any facet, decided exactly and fast.

Two strategies, both exact:

*brute force* (any surface): every point against every facet plane, in chunks.
  A matrix product gives each signed distance in float; a rigorous per-facet
  error bound (see :func:`_facet_bounds`) settles almost every entry, and the
  entries inside the bound go to the exact :func:`~.predicates.orient3d`,
  except those that cannot change the answer (:func:`_still_open`; many of
  them are settled in rounds, farthest first: :func:`_settle_undecided`).
*cones* (a surface already certified convex and closed, with a float point
  ``center`` verified strictly below every facet): the surface is then
  star-shaped around ``center``, so a point is outside the polytope iff it is
  strictly above the facet whose cone (from ``center``) contains it.  Points
  within a rigorous inscribed ball around ``center`` are inside outright; the
  others find their facet through a k-d tree on facet directions, confirmed by
  exact cone tests, with a walk across edges and brute force as fallbacks.

The second is what makes the full check of a 10^5-point hull cost about as
much as computing it.

Soundness of the float shortcuts (docs/checker.md): a matrix entry ``s`` is
decided only when it is finite (no intermediate overflowed) and beyond its
facet's bound, which carries ``2**-1000`` absolute terms for underflowed
products; :func:`_probe` decides with the same test, so every point it reports
is exactly outside.  The inscribed-ball shortcut (:func:`_deep_points`) uses
:func:`._geometry.inner_radius` (Shewchuk's bound, doubled) and, near the top
of the range, a power-of-two scaling verified exact on the planes and center.
No step holds all points x all facets, and a grossly wrong answer costs probes,
not ``n m`` entries (issue 33).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from ..contract import FaceSet
from ._geometry import cross3, inner_radius
from .predicates import orient2d, orient3d
from .topology import HalfEdges
from ._unique import unique_ints

__all__ = ["Containment", "check_containment3d", "check_containment2d"]

_EPS = 2.0**-53
_CHUNK = 2_000_000  # entries of the points x facets matrix held at once
_CONE_CHUNK = 500_000  # (point, cone edge) rows held at once: a big polygon face costs rows, not memory
_SMALL = 50_000  # up to this many point-facet entries, brute force (it beats the cone machinery there)
_ROUNDS_FROM = 4_096  # more undecided entries than this in a chunk are settled in rounds (_settle_undecided)
_WALK_STEPS = 64
#: Beyond this many (point, facet) entries, brute force probes first (:func:`_probe`).
_PROBE_FROM = 20_000_000
#: Probe facets per point, and probe points per facet.
_PROBES = 8


@dataclass
class Containment:
    """What the containment check found.

    Attributes
    ----------
    ok : bool
    outside : ndarray of int64
        Input points strictly outside some facet (sorted).
    magnitude : float
        Largest distance outside (float, for reporting).
    method : str
        ``"cones"`` or ``"brute"`` (or ``"cones+brute"`` when some points fell back).
    """

    ok: bool
    outside: np.ndarray
    magnitude: float
    method: str


def _row_max(v: np.ndarray) -> np.ndarray:
    """Largest entry of each row of a (k, d) array, column by column (numpy's axis=1 reduction is slow on narrow rows)."""
    out = v[:, 0].copy()
    for j in range(1, v.shape[1]):
        np.maximum(out, v[:, j], out=out)
    return out


def _row_sum(v: np.ndarray) -> np.ndarray:
    """Sum of each row of a (k, d) array, left to right (as ``v.sum(axis=1)`` adds so few terms)."""
    out = v[:, 0].copy()
    for j in range(1, v.shape[1]):
        out += v[:, j]
    return out


def _facet_bounds(planes: list[np.ndarray], pmax: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Float outward normals, offsets and a per-facet bound on the error of ``normal . p - offset``.

    The true value is ``n . (p - a)`` with ``n`` the exact normal of the
    facet's defining points (``(b - a) x (c - a)`` in 3D, the edge rotated
    clockwise in 2D), whose sign is the exact side.  The float normal's
    components are within 8 eps of their terms' magnitudes in 3D (twice the
    usual bound; in 2D the edge, rounded once, is within eps of its own
    magnitude), the dot products within 3 eps, and ``|p|, |a| <= pmax``; the
    bound sums these with a factor of two to spare and a 2**-1000 absolute term
    for underflow.
    """
    with np.errstate(all="ignore"):
        if len(planes) == 3:
            a, b, c = planes
            u, v = b - a, c - a
            n = cross3(u, v)
            terms = np.abs(np.stack([u[:, 1] * v[:, 2], u[:, 2] * v[:, 1], u[:, 2] * v[:, 0], u[:, 0] * v[:, 2], u[:, 0] * v[:, 1], u[:, 1] * v[:, 0]], axis=1))
            err = 8.0 * _EPS * (terms[:, 0::2] + terms[:, 1::2]) + 2.0**-1000
        else:
            a, b = planes
            u = b - a
            n = np.stack([u[:, 1], -u[:, 0]], axis=1)
            err = 0.0  # the edge rounded once: its error, eps |n|, is within the slack below
        offset = np.einsum("ij,ij->i", n, a)
        amax = _row_max(np.abs(a))
        slack = err + 16.0 * _EPS * np.abs(n)
        bound = 2.0 * _row_sum(slack) * (pmax + amax) + 2.0**-1000
    return n, offset, bound


def _distinct_planes(planes: list[np.ndarray]) -> np.ndarray:
    """Indices of facets whose oriented planes are pairwise distinct, exactly.

    Coplanar facets with the same orientation bound the same half-space, so
    one of each group suffices for containment.  This matters for surfaces on
    lattices, where thousands of triangles share a few planes and nearly every
    point-facet entry is an exact zero.  Groups are proposed by rounded float
    planes and every member is confirmed exactly (its vertices on the
    representative's plane, the same orientation in a projection where the
    representative does not collapse); unconfirmed facets stay.
    """
    a, b, c = planes
    m = len(a)
    with np.errstate(all="ignore"):
        n = np.cross(b - a, c - a)
        size = _row_max(np.abs(n))
        unit = n / size[:, None]
        off = np.einsum("ij,ij->i", unit, a)
        key = np.round(np.c_[unit, off / (np.abs(a).max() + 1.0)], 9)
    if not np.isfinite(key).all():
        return np.arange(m)
    _, group, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    group = group.ravel()
    if counts.max() == 1:
        return np.arange(m)
    order = np.argsort(group, kind="stable")
    first = np.r_[True, group[order][1:] != group[order][:-1]]
    rep = np.empty(len(counts), dtype=np.int64)
    rep[group[order[first]]] = order[first]
    r = rep[group]
    member = np.flatnonzero(r != np.arange(m))  # not empty: some group has two facets
    ra, rb, rc = a[r[member]], b[r[member]], c[r[member]]
    on = np.ones(len(member), dtype=bool)
    for x in (a, b, c):
        on &= orient3d(ra, rb, rc, x[member]) == 0
    # For a member on the representative's plane, every projection where the representative
    # does not collapse compares the orientations alike: any of them decides (the last here).
    same = np.zeros(len(member), dtype=bool)
    for i, j in ((0, 1), (1, 2), (2, 0)):
        s_rep = orient2d(ra[:, [i, j]], rb[:, [i, j]], rc[:, [i, j]])
        s_mem = orient2d(a[member][:, [i, j]], b[member][:, [i, j]], c[member][:, [i, j]])
        pick = s_rep != 0
        same[pick] = s_rep[pick] == s_mem[pick]
    return np.setdiff1d(np.arange(m), member[on & same])


def _brute(
    points: np.ndarray, planes: list[np.ndarray], plane_idx: np.ndarray, candidates: np.ndarray
) -> tuple[np.ndarray, float]:
    """Points of ``candidates`` strictly outside some plane (exact), chunked.

    Returns the points and the largest float distance outside (for reporting).
    """
    if not len(candidates) or not len(planes[0]):
        return np.zeros(0, dtype=np.int64), 0.0
    if len(planes) == 3 and len(planes[0]) > 1 and len(candidates) * len(planes[0]) > _SMALL:
        keep = _distinct_planes(planes)
        planes = [x[keep] for x in planes]
        plane_idx = plane_idx[keep]
    pmax = float(np.abs(points[candidates]).max())
    n, offset, bound = _facet_bounds(planes, pmax)
    norm = np.sqrt(np.einsum("ij,ij->i", n, n))  # einsum and sqrt of a non-negative raise no warning
    m = len(n)
    out = []
    worst = 0.0
    if len(candidates) * m > _PROBE_FROM:
        # A wrong answer of many facets: most points outside show it against a few probes.
        found, worst = _probe(points, candidates, n, offset, bound, norm)
        out.append(candidates[found])
        candidates = candidates[~found]
    chunk = max(1, _CHUNK // max(m, 1))
    for start in range(0, len(candidates), chunk):
        idx = candidates[start : start + chunk]
        with np.errstate(all="ignore"):
            s = points[idx] @ n.T - offset
            # Decided in floats: a finite s beyond a finite bound.  An s that overflowed
            # (inf, or NaN) decides nothing, as a term or a partial sum can overflow while
            # the exact sum is small and of either sign; a facet whose normal, offset or
            # bound is not finite has no finite s beyond its bound.
            sure = np.isfinite(s) & (np.abs(s) > bound)
        outside = sure & (s > 0)
        gray = ~sure
        gi, gf = np.nonzero(gray)
        if gi.size:
            own = np.any(plane_idx[gf] == idx[gi][:, None], axis=1)  # a facet's own vertex is on it
            gi, gf = gi[~own], gf[~own]
        if gi.size:
            gi, gf = _still_open(gi, gf, outside, s, norm, worst)
        if gi.size:
            _settle_undecided(gi, gf, points[idx], planes, outside, s, norm, worst)
        hit = outside.any(axis=1)
        if hit.any():
            with np.errstate(all="ignore"):
                dist = np.where(outside[hit], s[hit] / norm, 0.0)
            worst = max(worst, float(np.nan_to_num(dist, nan=0.0, posinf=0.0, neginf=0.0).max()))
        out.append(idx[hit])
    return np.concatenate(out), max(worst, 0.0)


def _probe(points: np.ndarray, candidates: np.ndarray, n: np.ndarray, offset: np.ndarray, bound: np.ndarray,
           norm: np.ndarray) -> tuple[np.ndarray, float]:
    """Which candidates are surely outside some facet, from a linear number of probe entries.

    Each point meets :data:`_PROBES` facets spread over the surface, and each
    facet the :data:`_PROBES` points farthest along its normal direction
    that a k-d tree on the points' directions proposes.  An entry is decided
    exactly as in :func:`_brute` (a finite float value beyond the facet's
    rigorous bound), so every point returned is exactly outside; the others
    go through the full scan.  This turns the judgement of a grossly wrong
    answer (a reversed 10^5-point sphere: every point outside nearly every
    facet) from n x m entries into O((n + m) log n).

    Returns the mask of candidates found outside, and the largest distance
    outside among the probed entries: for those points the reported magnitude
    is a lower bound on the largest over every facet (docs/checker.md).
    """
    pts = points[candidates]
    m = len(n)
    r = min(_PROBES, m)
    found = np.zeros(len(candidates), dtype=bool)
    worst = 0.0
    spread = np.linspace(0, m - 1, r).astype(np.int64)  # the same facets for every point, spread over the answer
    rows = max(1, _CHUNK // r)
    with np.errstate(all="ignore"):
        for start in range(0, len(pts), rows):
            part = slice(start, start + rows)
            s = pts[part] @ n[spread].T - offset[spread]
            sure = np.isfinite(s) & (s > bound[spread])
            found[part] |= sure.any(axis=1)
            if sure.any():
                worst = max(worst, float(np.max(np.where(sure, s / norm[spread], 0.0))))
        # Per facet, the points farthest along its normal, by direction from the points' centroid.
        center = pts.mean(axis=0)
        if np.isfinite(center).all():
            tree = cKDTree(_unit_rows(pts - center))
            _, near = tree.query(_unit_rows(n), k=r)
            near = np.minimum(near.reshape(m, r), len(pts) - 1)
            for j in range(r):
                p = near[:, j]
                s = np.einsum("ij,ij->i", pts[p], n) - offset
                sure = np.isfinite(s) & (s > bound)
                found[p[sure]] = True
                if sure.any():
                    worst = max(worst, float(np.max(s[sure] / norm[sure])))
    return found, worst if np.isfinite(worst) else 0.0


def _exactly_outside(gi: np.ndarray, gf: np.ndarray, pts: np.ndarray, planes: list[np.ndarray],
                     outside: np.ndarray) -> None:
    """Mark the entries ``(gi, gf)`` whose point ``pts[gi]`` is strictly outside facet ``gf`` (exact signs)."""
    p = pts[gi]
    if len(planes) == 3:
        sign = orient3d(planes[0][gf], planes[1][gf], planes[2][gf], p, planes=gf)
    else:
        sign = orient2d(planes[0][gf], planes[1][gf], p)
    outside[gi[sign < 0], gf[sign < 0]] = True


def _settle_undecided(gi: np.ndarray, gf: np.ndarray, pts: np.ndarray, planes: list[np.ndarray],
                      outside: np.ndarray, s: np.ndarray, norm: np.ndarray, worst: float) -> None:
    """Settle the undecided entries ``(gi, gf)`` of a chunk exactly, into ``outside``, skipping what cannot matter.

    Up to :data:`_ROUNDS_FROM` entries, all at once.  More come from surfaces
    whose every plane nearly passes through every point (a wrong hull of
    1483 faces over 90 near-collinear points: 128 000 entries out of
    133 000, and all 90 points outside some facet).  Those are settled in
    rounds: each point's entry farthest outside in float first, then 4, 16
    ... more per point, and after each round the rule of :func:`_still_open`
    (:func:`_open`) drops the entries that can no longer change the answer
    (those of points found outside that are not farther than the farthest
    outside entry known).  A point inside still has every entry settled;
    the float distances only decide the order, so how soon the others stop.
    """
    if gi.size <= _ROUNDS_FROM:
        _exactly_outside(gi, gf, pts, planes, outside)
        return
    with np.errstate(all="ignore"):
        dist = s[gi, gf] / norm[gf]  # each entry's float distance, computed once for every round
    key = np.where(np.isfinite(dist), dist, -np.finfo(np.float64).max)  # an order only: last, above the fill
    # The first round without sorting: each point's farthest entry.
    farthest = np.full(outside.shape, -np.inf)
    farthest[gi, gf] = key
    best = farthest.argmax(axis=1)
    points_open = unique_ints(gi)
    _exactly_outside(points_open, best[points_open], pts, planes, outside)
    keep = _open(gi, dist, outside, s, norm, worst) & (gf != best[gi])
    gi, gf, dist, key = gi[keep], gf[keep], dist[keep], key[keep]
    order = np.lexsort((-key, gi))  # by point, and within a point the farthest first
    gi, gf, dist = gi[order], gf[order], dist[order]
    first = np.r_[0, np.flatnonzero(gi[1:] != gi[:-1]) + 1]
    rank = np.arange(gi.size) - np.repeat(first, np.diff(np.r_[first, gi.size]))
    take = 4
    while gi.size:
        now = rank < take
        _exactly_outside(gi[now], gf[now], pts, planes, outside)
        gi, gf, dist, rank = gi[~now], gf[~now], dist[~now], rank[~now]
        keep = _open(gi, dist, outside, s, norm, worst)
        gi, gf, dist, rank = gi[keep], gf[keep], dist[keep], rank[keep]
        take *= 4


def _still_open(gi: np.ndarray, gf: np.ndarray, outside: np.ndarray, s: np.ndarray, norm: np.ndarray,
                worst: float) -> tuple[np.ndarray, np.ndarray]:
    """The undecided (point, facet) entries whose exact sign can still change what :func:`_brute` returns.

    A point the float test already puts outside some facet is outside
    whatever its other signs are: its undecided entries matter only for the
    largest distance reported, and only where their float distance exceeds
    the largest one known (``worst`` so far, or a decided entry of the same
    chunk).  Dropping the others changes neither the points nor the
    distance returned, and spares the exact stages most of a grossly wrong
    hull's entries (a wrong hull of 100 near-collinear points: 0.74 s).
    """
    with np.errstate(all="ignore"):  # a zero normal or an overflow: inf and NaN
        keep = _open(gi, s[gi, gf] / norm[gf], outside, s, norm, worst)
    return gi[keep], gf[keep]


def _open(gi: np.ndarray, dist: np.ndarray, outside: np.ndarray, s: np.ndarray, norm: np.ndarray,
          worst: float) -> np.ndarray:
    """Which entries of points ``gi`` with float distances ``dist`` :func:`_still_open` keeps, as a mask."""
    hit = outside.any(axis=1)
    if not hit.any():
        return np.ones(gi.size, dtype=bool)
    with np.errstate(all="ignore"):  # a zero normal or an overflow: inf and NaN, reported as 0 (_brute)
        known = s[hit] / norm
        known = known[outside[hit] & np.isfinite(known)]
        bar = max(worst, float(known.max())) if known.size else worst
        return ~hit[gi] | (dist > bar)


def _unit_rows(v: np.ndarray) -> np.ndarray:
    """Rows scaled to unit length, for candidate search only (no overflow at 1e300; zero rows stay zero)."""
    top = _row_max(np.abs(v))
    v = v / np.where(top > 0, top, 1.0)[:, None]  # first to [-1, 1]: the norm cannot overflow
    norm = np.sqrt(np.einsum("ij,ij->i", v, v))
    return np.nan_to_num(v / np.where(norm > 0, norm, 1.0)[:, None])


def _deep_points(points: np.ndarray, planes: list[np.ndarray], center: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Points within a rigorous inscribed ball around ``center``: strictly below every plane.

    This needs no convexity: every plane is at least the ball's radius away
    from ``center``, which is verified strictly below each of them.
    """
    scale = _ball_scale(planes, center)
    if scale != 1.0:
        # Near the top of the range the radius' float products overflow (and it would be 0):
        # measure in units scaled by a power of two that is exact on the planes and the center.
        # A point's own scaled coordinates may round (below the normal range), by at most
        # 2**-1075 each: covered by the absolute slack below.
        planes = [x * scale for x in planes]
        center = center * scale
        points = points * scale
    r = inner_radius(planes, center)
    with np.errstate(all="ignore"):
        rel = points - center
        dist = np.sqrt(np.einsum("ij,ij->i", rel, rel)) * (1.0 + 1e-12) + 2.0**-500
    return rel, dist < r


def _ball_scale(planes: list[np.ndarray], center: np.ndarray) -> float:
    """A power of two bringing the planes and ``center`` below 1, when that scaling is exact on them; else 1."""
    top = max([float(np.abs(center).max())] + [float(np.abs(x).max()) for x in planes if x.size])
    if not 0.0 < top <= 2.0**-200 and not top >= 2.0**200:
        return 1.0
    scale = 2.0 ** -int(np.frexp(top)[1])
    if scale == 0.0 or not np.isfinite(scale):
        return 1.0
    with np.errstate(all="ignore"):
        exact = all(np.array_equal((x * scale) / scale, x) for x in planes + [center])
    return scale if exact else 1.0


# --------------------------------------------------------------------------- 3D


def _cone_planes(points: np.ndarray, center: np.ndarray, he: HalfEdges, pmax: float):
    """Per half-edge (u, v): the plane through ``center``, u and v, as float normal, offset and error bound.

    ``normal . p - offset`` approximates ``-orient3d(center, u, v, p)`` within
    the bound (:func:`_facet_bounds`): positive on the cone's inner side.
    """
    return _facet_bounds([center[None, :], points[he.src], points[he.dst]], pmax)


def _in_cones(points, center, he: HalfEdges, faces: FaceSet, pts: np.ndarray, cand: np.ndarray, cones):
    """For each (point, face) pair: all edge signs of the face's cone, reduced per pair.

    Returns ``inside`` (point in the closed cone) and, per pair, one half-edge
    whose plane separates the point from the cone (-1 when inside).  Each
    sign comes from the float cone planes (:func:`_cone_planes`) where their
    bound decides it, from the exact orient3d otherwise.  Pairs are processed
    in chunks of at most ``_CONE_CHUNK`` cone edges, so a polygon face with
    thousands of vertices costs time, not memory.
    """
    normal, offset, bound = cones
    sizes = faces.sizes[cand]
    inside = np.zeros(len(cand), dtype=bool)
    exit_edge = np.full(len(cand), -1)
    ends = np.cumsum(sizes)
    lo = 0
    while lo < len(cand):
        hi = max(lo + 1, int(np.searchsorted(ends, ends[lo] - sizes[lo] + _CONE_CHUNK, side="right")))
        part = slice(lo, hi)
        sz = sizes[part]
        rows = np.repeat(np.arange(hi - lo), sz)
        starts = np.cumsum(sz) - sz
        edge = np.repeat(faces.offsets[:-1][cand[part]], sz) + np.arange(len(rows)) - np.repeat(starts, sz)
        p = points[pts[part][rows]]
        with np.errstate(all="ignore"):
            s = np.einsum("ij,ij->i", normal[edge], p) - offset[edge]
            sure = np.isfinite(s) & (np.abs(s) > bound[edge])  # an overflowed s decides nothing
        bad = sure & (s < 0)
        gray = np.flatnonzero(~sure)
        if gray.size:
            e = edge[gray]
            bad[gray] = orient3d(center, points[he.src[e]], points[he.dst[e]], p[gray]) > 0
        inside[part] = ~np.logical_or.reduceat(bad, starts)
        # The first separating half-edge of each pair (a walk step crosses it).
        bad_rows = np.flatnonzero(bad)
        if bad_rows.size:
            first_bad, where = np.unique(rows[bad_rows], return_index=True)
            exit_edge[lo + first_bad] = edge[bad_rows[where]]
        lo = hi
    return inside, exit_edge


def check_containment3d(
    points: np.ndarray,
    faces: FaceSet,
    plane: np.ndarray,
    *,
    certified: bool = False,
    center: np.ndarray | None = None,
    he: HalfEdges | None = None,
    k: int = 1,
) -> Containment:
    """Check that no point lies strictly outside any facet plane of a 3D surface.

    Parameters
    ----------
    points : ndarray of shape (n, 3), float64
    faces : FaceSet
    plane : ndarray of shape (m, 3), int64
        Each face's plane triple (-1 rows for degenerate faces, which have no
        plane and are skipped: they are convexity failures).
    certified : bool
        The surface passed convexity and manifoldness: the cone strategy applies.
    center : ndarray of shape (3,) or None
        A float point verified strictly below every facet: required for cones,
        and used by both strategies to settle the points of an inscribed ball.
    he : HalfEdges or None
        Required for cones (cone edges and walking).
    k : int
        Candidate facets per point from the k-d tree.

    Returns
    -------
    Containment
    """
    n = len(points)
    has = np.flatnonzero(plane[:, 0] >= 0)
    tri = plane[has]
    planes = [points[tri[:, 0]], points[tri[:, 1]], points[tri[:, 2]]]
    cones = certified and he is not None and center is not None
    if n * len(has) <= _SMALL or center is None or not len(has):
        todo = np.ones(n, dtype=bool)
        if certified and center is not None:  # the surface's own vertices lie on the certified convex surface
            todo[faces.indices] = False
        candidates = np.flatnonzero(todo)
        outside, worst = _brute(points, planes, tri, candidates)
        return Containment(not outside.size, outside, worst, "brute")
    rel, deep = _deep_points(points, planes, center)
    if not cones:
        # Not certified convex: still, the inscribed ball is below every plane.
        outside, worst = _brute(points, planes, tri, np.flatnonzero(~deep))
        return Containment(not outside.size, outside, worst, "brute")
    deep[faces.indices] = True  # the surface's own vertices lie on the certified convex surface
    todo = np.flatnonzero(~deep)
    if not todo.size:
        return Containment(True, np.zeros(0, np.int64), 0.0, "cones")

    # Candidate facets by direction from the center.
    face_ids = has
    with np.errstate(all="ignore"):
        centroid = _unit_rows((planes[0] + planes[1] + planes[2]) / 3.0 - center)
        dirs = _unit_rows(rel[todo])
    kk = min(k, len(face_ids))
    cones = _cone_planes(points, center, he, float(np.abs(points[todo]).max()))
    _, nearest = cKDTree(centroid).query(dirs, k=kk)
    # A direction the tree could not place (index == len) just gets no candidate: the
    # walk and brute force below still decide every point exactly.
    nearest = np.minimum(nearest.reshape(len(todo), kk), len(face_ids) - 1)
    located = np.full(len(todo), -1)
    exits = np.full(len(todo), -1)
    for j in range(kk):
        open_ = np.flatnonzero(located < 0)
        if not open_.size:
            break
        cand = face_ids[nearest[open_, j]]
        inside, exit_edge = _in_cones(points, center, he, faces, todo[open_], cand, cones)
        located[open_[inside]] = cand[inside]
        if j == 0:
            exits[open_] = exit_edge
    # Walk across the separating edge from the first candidate.
    open_ = np.flatnonzero(located < 0)
    walk = exits[open_]
    for _ in range(_WALK_STEPS):
        if not open_.size:
            break
        twin = np.where(walk >= 0, he.twin[np.maximum(walk, 0)], -1)
        alive = twin >= 0
        open_, twin = open_[alive], twin[alive]  # (none left: the next round ends the walk)
        cand = he.face[twin]
        inside, walk = _in_cones(points, center, he, faces, todo[open_], cand, cones)
        located[open_[inside]] = cand[inside]
        open_, walk = open_[~inside], walk[~inside]
    lost = todo[located < 0]

    found = np.flatnonzero(located >= 0)
    f = located[found]
    sign = orient3d(points[plane[f, 0]], points[plane[f, 1]], points[plane[f, 2]], points[todo[found]])
    outside = todo[found][sign < 0]
    method = "cones"
    if lost.size:
        outside = np.concatenate([outside, _brute(points, planes, tri, lost)[0]])
        method = "cones+brute"
    # The magnitude (reporting only): the outside points against every plane.
    outside, worst = _brute(points, planes, tri, unique_ints(outside))
    return Containment(not outside.size, outside, worst, method)


# --------------------------------------------------------------------------- 2D


def check_containment2d(
    points: np.ndarray,
    polygon: np.ndarray,
    *,
    certified: bool = False,
    center: np.ndarray | None = None,
) -> Containment:
    """Check that no point lies strictly right of any edge of a 2D polygon.

    Parameters
    ----------
    points : ndarray of shape (n, 2), float64
    polygon : ndarray of shape (k,), int64
        Vertex indices, counter-clockwise.  Zero-length edges are skipped
        (they are convexity failures).
    certified : bool
        The polygon passed convexity and manifoldness: the angular strategy applies.
    center : ndarray of shape (2,) or None
        A float point verified strictly left of every edge: required for the
        angular strategy, and used by both to settle an inscribed disc.

    Returns
    -------
    Containment
    """
    n = len(points)
    a_idx, b_idx = polygon, np.roll(polygon, -1)
    keep = np.any(points[a_idx] != points[b_idx], axis=1)
    a_idx, b_idx = a_idx[keep], b_idx[keep]
    planes = [points[a_idx], points[b_idx]]
    plane_idx = np.stack([a_idx, b_idx], axis=1)
    if n * len(a_idx) <= _SMALL or center is None or not len(a_idx):
        todo = np.ones(n, dtype=bool)
        if certified and center is not None and len(a_idx) >= 3:  # vertices of a certified convex polygon
            todo[polygon] = False
        candidates = np.flatnonzero(todo)
        outside, worst = _brute(points, planes, plane_idx, candidates)
        return Containment(not outside.size, outside, worst, "brute")
    rel, deep = _deep_points(points, planes, center)
    if not (certified and len(a_idx) >= 3):
        outside, worst = _brute(points, planes, plane_idx, np.flatnonzero(~deep))
        return Containment(not outside.size, outside, worst, "brute")
    deep[polygon] = True  # the polygon's own vertices lie on the certified convex polygon
    todo = np.flatnonzero(~deep)
    if not todo.size:
        return Containment(True, np.zeros(0, np.int64), 0.0, "cones")
    k = len(a_idx)
    vrel = planes[0] - center
    theta = np.arctan2(vrel[:, 1], vrel[:, 0])
    start = int(np.argmin(theta))
    order = (np.arange(k) + start) % k  # edges in increasing angle of their first vertex
    theta_sorted = theta[order]
    tp = np.arctan2(rel[todo, 1], rel[todo, 0])
    guess = order[(np.searchsorted(theta_sorted, tp, side="right") - 1) % k]
    located = np.full(len(todo), -1)
    for step in (0, -1, 1, -2, 2):
        open_ = np.flatnonzero(located < 0)
        if not open_.size:
            break
        e = (guess[open_] + step) % k
        p = points[todo[open_]]
        inside = (orient2d(center, planes[0][e], p) >= 0) & (orient2d(center, planes[1][e], p) <= 0)
        located[open_[inside]] = e[inside]
    lost = todo[located < 0]
    found = np.flatnonzero(located >= 0)
    e = located[found]
    sign = orient2d(planes[0][e], planes[1][e], points[todo[found]])
    outside = todo[found][sign < 0]
    method = "cones"
    if lost.size:
        outside = np.concatenate([outside, _brute(points, planes, plane_idx, lost)[0]])
        method = "cones+brute"
    outside, worst = _brute(points, planes, plane_idx, unique_ints(outside))
    return Containment(not outside.size, outside, worst, method)
