"""Containment (``hullstress/checker/containment.py``), pinned where the mutation run found it loose.

Each test here was written against mutants of ``containment.py`` that survived the
rest of the fast suite (``tools/mutation.sh 'hullstress.checker.containment.*'``,
docs/testing.md "Mutation testing").  Both exact strategies are reached: brute force (at most
``_SMALL`` point-facet entries, no centre, or a surface not certified) and the cones
around a certified centre (2D: the angular search), with points exactly on, one ulp
inside and one ulp outside facets, at unit, ~1e-300 and ~1e300 scales.  Every
expected answer comes from exact arithmetic written here (integers, or Fractions of
the doubles' exact values) or from the documented behaviour, never from the
checker's own output.  Scaling by a power of two is exact, so an input built at
unit scale keeps its answer at 2**-1000 and 2**1000.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest
from scipy.spatial import ConvexHull

from hullstress.checker import containment as cm
from hullstress.checker._geometry import inner_radius
from hullstress.checker.containment import check_containment2d, check_containment3d
from hullstress.checker.topology import half_edges
from hullstress.contract import FaceSet

SCALES = [1.0, 2.0**-1000, 2.0**1000]


def _up(x: float) -> float:
    return math.nextafter(x, math.inf)


def _down(x: float) -> float:
    return math.nextafter(x, -math.inf)


# --------------------------------------------------------------------------- the exact oracle


def _exact_outside(points: np.ndarray, facets: np.ndarray, scale: float = 1.0) -> list[int]:
    """Indices of ``points`` strictly outside some facet, exactly.

    ``facets`` holds vertex indices: (m, 3) outward triangles in 3D, (m, 2)
    counter-clockwise edges in 2D; their corners are integers times ``scale`` (a power
    of two).  The outward normal is ``(b - a) x (c - a)`` in 3D, the edge ``b - a``
    rotated clockwise in 2D; a point is outside when ``normal . p > normal . a``.
    With small corners (below 2**12), points that are small integers times ``scale``
    are decided in int64 (every product fits); the others in Python integers and
    Fractions.
    """
    pts = np.asarray(points, dtype=np.float64)
    with np.errstate(over="ignore"):
        unit = pts / scale  # exact for a power of two where finite (checked below, point by point)
    for k in range(facets.shape[1]):
        c = unit[facets[:, k]]
        assert np.array_equal(c, np.round(c)) and np.array_equal(c * scale, pts[facets[:, k]])
    corners = [[[int(x) for x in row] for row in unit[facets[:, k]]] for k in range(facets.shape[1])]
    normals = []
    for corner in zip(*corners):
        a = corner[0]
        if len(corner) == 3:
            u = [corner[1][k] - a[k] for k in range(3)]
            v = [corner[2][k] - a[k] for k in range(3)]
            n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
        else:
            n = [corner[1][1] - a[1], a[0] - corner[1][0]]
        normals.append((n, sum(x * y for x, y in zip(n, a))))
    out = np.zeros(len(pts), dtype=bool)
    whole = np.all(np.abs(unit) < 2**20, axis=1) & np.all(unit == np.round(unit), axis=1)
    whole &= np.all(pts == unit * scale, axis=1)
    if max(abs(x) for c in corners for row in c for x in row) < 2**12:
        n = np.array([r for r, _ in normals], dtype=np.int64)
        off = np.array([o for _, o in normals], dtype=np.int64)
        out[whole] = (unit[whole].astype(np.int64) @ n.T > off).any(axis=1)
    else:
        whole[:] = False
    # The rest in Python integers: point = X / den, scale = num_s / den_s, so the test
    # normal . X / den > off * num_s / den_s becomes (normal . X) * den_s > off * num_s * den.
    num_s, den_s = Fraction(scale).as_integer_ratio()
    n_obj = np.array([r for r, _ in normals], dtype=object)
    off_obj = np.array([o * num_s for _, o in normals], dtype=object)
    for i in np.flatnonzero(~whole):
        x = [Fraction(float(t)) for t in pts[i]]
        den = max(f.denominator for f in x)  # powers of two: the largest is a common denominator
        big = np.array([int(f * den) for f in x], dtype=object)
        out[i] = bool(((n_obj @ big) * den_s > off_obj * den).any())
    return np.flatnonzero(out).tolist()


# --------------------------------------------------------------------------- a tetrahedron, brute force

_TET = np.array([[0, 0, 0], [4, 0, 0], [0, 4, 0], [0, 0, 4]], dtype=np.float64)
_TET_FACES = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]  # outward (counter-clockwise seen from outside)


def _tet_probes(s: float) -> np.ndarray:
    """Points exactly on the oblique face x + y + z = 4 s, one ulp inside and one ulp outside it,
    on / one ulp (a subnormal) beyond the face y = 0, and s / 32 beyond the oblique face (its
    float distance, 16 s**2 (x + y + z) - 64 s**3, is then s**3 / 2: at unit scale below 1)."""
    return np.array([
        [s, s, 2 * s], [s, s, _up(2 * s)], [s, s, _down(2 * s)],
        [_up(s), s, 2 * s], [s, 0.0, s], [s, -0.0, s], [s, _down(0.0), s],
        [s, s, s], [2 * s, 2 * s, 0.0], [_up(2 * s), 2 * s, 0.0], [s, s, 2 * s + s / 32],
    ])


@pytest.mark.parametrize("scale", [*SCALES, 2.0**40])
def test_brute_tetrahedron_on_and_one_ulp_from_its_faces(scale):
    pts = np.vstack([_TET * scale, _tet_probes(scale)])
    fs = FaceSet.from_polygons(_TET_FACES)
    plane = np.array(_TET_FACES, dtype=np.int64)
    want = _exact_outside(pts, plane, scale)
    # By hand: the ulp beyond x + y + z = 4 (rows 5, 7, 13), below y = 0 (row 10), and s / 32 beyond (14).
    assert want == [5, 7, 10, 13, 14]
    res = check_containment3d(pts, fs, plane)
    assert res.outside.tolist() == want and res.ok is False and res.method == "brute"
    # The magnitude, the largest distance outside, is row 14's: (s / 32) / sqrt(3).  It is
    # a float report: where the float distances underflow (2**-1000) or overflow (2**1000)
    # it is less, down to 0, but never inf or NaN.
    top = scale / 32 / math.sqrt(3)
    if scale in (1.0, 2.0**40):
        assert res.magnitude == pytest.approx(top, rel=1e-12)
    else:
        assert 0.0 <= res.magnitude <= top


# --------------------------------------------------------------------------- a convex ball surface, both strategies


def _fibonacci_shell(count: int, radius: int) -> np.ndarray:
    """``count`` integer points near a sphere of ``radius`` (Fibonacci spiral), times 6: then
    the centroid of three of them and the midpoint of two are integer points too."""
    golden = math.pi * (3 - math.sqrt(5))
    pts = []
    for i in range(count):
        z = 1 - (2 * i + 1) / count
        r = math.sqrt(1 - z * z)
        pts.append((round(r * math.cos(golden * i) * radius), round(r * math.sin(golden * i) * radius), round(z * radius)))
    return np.unique(np.array(pts, dtype=np.int64), axis=0) * 6


def _ball_surface(count: int = 100, radius: int = 40) -> tuple[np.ndarray, np.ndarray]:
    """A convex closed triangle mesh around the origin on integer points, outward, checked in integers."""
    shell = _fibonacci_shell(count, radius)
    shell = shell[ConvexHull(shell).vertices]
    tri = ConvexHull(shell).simplices.astype(np.int64)
    a, b, c = shell[tri[:, 0]], shell[tri[:, 1]], shell[tri[:, 2]]
    inward = np.einsum("ij,ij->i", np.cross(b - a, c - a), a) < 0  # the origin above the plane
    tri[inward] = tri[inward][:, ::-1]
    a, b, c = shell[tri[:, 0]], shell[tri[:, 1]], shell[tri[:, 2]]
    n = np.cross(b - a, c - a)
    off = np.einsum("ij,ij->i", n, a)
    assert (off > 0).all()  # the origin strictly below every facet
    assert not (shell @ n.T > off).any()  # convex: no corner strictly above any facet
    return shell, tri


def _ball_probes(shell: np.ndarray, tri: np.ndarray, seed: int) -> np.ndarray:
    """Query points around the ball surface, at unit scale: scattered integer points inside
    and outside, facet centroids and edge midpoints (exactly on the surface), the centroids
    one ulp beyond and one ulp within their facet along the normal's largest component,
    corners one ulp off along each axis (beyond some facets of the corner, within others),
    edge midpoints scaled by 3 (outside, exactly on the plane of a cone) and some of them
    2**-17 off it (a float distance to that plane below 1), the corners' coordinates again
    under other indices, and points far outside."""
    rng = np.random.default_rng(seed)
    a, b, c = shell[tri[:, 0]], shell[tri[:, 1]], shell[tri[:, 2]]
    n = np.cross(b - a, c - a)
    centroid = (a + b + c) // 3
    nudged = []
    for f in range(0, len(tri), 4):
        k = int(np.argmax(np.abs(n[f])))
        for step in (_up, _down):
            p = centroid[f].astype(np.float64)
            p[k] = step(p[k])
            nudged.append(p)
    for v in shell[::4].astype(np.float64):
        for k in range(3):
            for step in (_up, _down):
                p = v.copy()
                p[k] = step(p[k])
                nudged.append(p)
    ray = (a + b)[::5] // 2 * 3  # on the plane of the cone through the edge (a, b)
    return np.vstack([
        rng.integers(-300, 301, size=(120, 3)), centroid, (a + b) // 2, np.array(nudged), ray,
        ray[::2] + [2.0**-17, 0.0, 0.0], shell[::7], shell[::9] * 5, [[0, 0, 0], [0, 0, 1]],
    ]).astype(np.float64)


def _ball_case(seed: int, scale: float):
    shell, tri = _ball_surface()
    pts = np.vstack([shell.astype(np.float64), _ball_probes(shell, tri, seed)]) * scale
    fs = FaceSet.from_polygons(tri.tolist())
    return pts, tri, fs


@pytest.mark.parametrize(("scale", "k"), [(1.0, 1), (1.0, 3), (2.0**-1000, 1), (2.0**1000, 2)])
def test_cones_on_a_ball_surface_against_integers(scale, k):
    # A certified surface with a centre: the cones decide every point, no fallback needed
    # on a surface this regular (documented: "cones", "cones+brute" only when some fell back).
    pts, tri, fs = _ball_case(5, scale)
    want = _exact_outside(pts, tri, scale)
    assert 50 < len(want) < len(pts) - 500 and len(pts) * len(tri) > cm._SMALL
    he = half_edges(fs, len(pts))
    res = check_containment3d(pts, fs, tri, certified=True, center=np.zeros(3), he=he, k=k)
    assert res.outside.tolist() == want and res.ok is False and res.method == "cones"
    assert res.outside.dtype == np.int64


@pytest.mark.parametrize("scale", [1.0, 2.0**40])
def test_brute_on_a_ball_surface_against_integers(scale):
    # Not certified, or no centre: brute force (at the extreme scales nearly every entry
    # goes to the exact predicate, so not those; the tetrahedron covers them).  At 2**40
    # the normals are about 2**90: the bound grows with them.
    pts, tri, fs = _ball_case(5, scale)
    want = _exact_outside(pts, tri, scale)
    he = half_edges(fs, len(pts))
    for kwargs in ({"certified": False, "center": np.zeros(3), "he": he}, {"certified": True, "he": he}, {}):
        res = check_containment3d(pts, fs, tri, **kwargs)
        assert res.outside.tolist() == want and res.ok is False and res.method == "brute", kwargs


# --------------------------------------------------------------------------- repeated and parallel facet planes


def _lattice_cube(k: int, side: int) -> tuple[np.ndarray, np.ndarray]:
    """The cube [0, side]^3 with each face cut into k x k squares of two triangles each,
    outward, plus one big triangle per face (half the face): 6 planes, many facets each."""
    index: dict[tuple[int, int, int], int] = {}

    def vid(p) -> int:
        return index.setdefault(tuple(int(x) for x in p), len(index))

    tris = []
    step = side // k
    for axis in range(3):
        for level, outward in ((0, -1), (side, 1)):
            def at(u, v):
                p = [0, 0, 0]
                p[axis], p[(axis + 1) % 3], p[(axis + 2) % 3] = level, u, v
                return p

            # (axis + 1, axis + 2) is a right-handed pair: (u, v) counter-clockwise faces +axis.
            quads = [(at(i * step, j * step), at((i + 1) * step, j * step), at((i + 1) * step, (j + 1) * step),
                      at(i * step, (j + 1) * step)) for i in range(k) for j in range(k)]
            quads.append((at(0, 0), at(side, 0), at(side, side), at(0, side)))
            for n, (p, q, r, s) in enumerate(quads):
                pair = [(p, q, r), (p, r, s)] if n < len(quads) - 1 else [(p, q, s)]
                for t in pair:
                    tris.append([vid(x) for x in (t if outward > 0 else t[::-1])])
    pts = np.zeros((len(index), 3), dtype=np.int64)
    for p, i in index.items():
        pts[i] = p
    tri = np.array(tris, dtype=np.int64)
    a, b, c = pts[tri[:, 0]], pts[tri[:, 1]], pts[tri[:, 2]]
    n = np.cross(b - a, c - a)
    assert (np.einsum("ij,ij->i", n, side - 2 * a) < 0).all()  # outward: the centre below every facet
    return pts, tri


def _terraces(levels, size: int) -> tuple[np.ndarray, np.ndarray]:
    """Horizontal facets facing +z on the planes z = level: a 2 x 2 grid of squares over
    [0, size]^2 on each, two triangles per square (parallel planes, many facets each)."""
    pts, tri = [], []
    h = size // 2
    for z in levels:
        for i in range(2):
            for j in range(2):
                base = len(pts)
                pts += [[i * h, j * h, z], [(i + 1) * h, j * h, z], [(i + 1) * h, (j + 1) * h, z], [i * h, (j + 1) * h, z]]
                tri += [[base, base + 1, base + 2], [base, base + 2, base + 3]]
    return np.array(pts, dtype=np.int64), np.array(tri, dtype=np.int64)


def _plane_of(pts: np.ndarray, t) -> tuple:
    """A facet's oriented plane exactly: its normal scaled to a largest component of magnitude 1, and its offset (Fractions)."""
    a, b, c = ([Fraction(float(x)) for x in pts[i]] for i in t)
    n = _exact_normal(a, b, c)
    g = max(abs(x) for x in n)
    n = tuple(x / g for x in n)
    return n, sum(x * y for x, y in zip(n, a))


def _dedup(pts: np.ndarray, tri: np.ndarray) -> np.ndarray:
    f = np.asarray(pts, dtype=np.float64)
    return cm._distinct_planes([f[tri[:, 0]], f[tri[:, 1]], f[tri[:, 2]]])


def test_distinct_planes_keeps_one_facet_of_each_lattice_plane():
    # Documented: coplanar facets with the same orientation bound the same half-space,
    # one of each group suffices, and on a lattice every member is confirmed exactly.
    # (The float keys of one plane are bit-identical here: the unit normal is an axis and
    # its offset a coordinate, exact, so every member is proposed with its representative.)
    pts, tri = _lattice_cube(4, 8)
    rng = np.random.default_rng(3)
    tz, tt = _terraces([1, 2, 3, 5], 8)  # parallel planes close together, relative to the offsets' scale
    cases = [(pts, tri, 6), (pts, tri[rng.permutation(len(tri))], 6), (pts, np.roll(tri, 1, axis=1), 6),
             (pts / 8 - 0.5, tri, 6),  # the cube [-0.5, 0.5]^3
             (pts / 4 - 1, tri, 6),  # the cube [-1, 1]^3: the largest coordinate is 1
             (np.vstack([pts, tz]), np.vstack([tri, tt + len(pts)]), 10)]  # 4 more planes, z = 1, 2, 3, 5
    for p, t, count in cases:
        keep = _dedup(p, t)
        planes = {_plane_of(p, x) for x in t}
        assert len(planes) == count
        assert sorted(_plane_of(p, t[i]) for i in keep) == sorted(planes)
        assert keep.dtype == np.int64
    # Two facets on one plane (the largest group has two members): one is enough.
    two = tri[[0, 1, 40]]
    assert _plane_of(pts, two[0]) == _plane_of(pts, two[1]) != _plane_of(pts, two[2])
    assert len(_dedup(pts, two)) == 2


# A sliver in the plane x = 0 whose exact normal points to +x while the float cross product of
# its rounded edge vectors points to -x: the rounded plane key groups it with the -x facets of
# that plane, and only the exact orientation test (in the yz projection: the xy projection of
# the plane collapses) keeps it.
_SLIVER = [[0.0, -3107.6607442293016, -327.31021877988496], [0.0, 160367.7352633019, 16890.517606124187],
           [0.0, -3.132201846249246, -0.3298949775847717]]


def _exact_normal(a, b, c) -> list[Fraction]:
    a, b, c = ([Fraction(float(x)) for x in p] for p in (a, b, c))
    u = [b[k] - a[k] for k in range(3)]
    v = [c[k] - a[k] for k in range(3)]
    return [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]


def _near_plane_facets() -> list[list[list[float]]]:
    """Facets around the plane x = 0 facing -x: the representative (0), the same plane and
    orientation again (1: redundant), the representative with one corner 2**-40 off the plane
    (2, 3, 4), the parallel plane x = -2**-40 (5), the sliver (6), the representative reversed (7)."""
    t = 2.0**-40
    rep = [[0.0, 0.0, 0.0], [0.0, 0.0, 4.0], [0.0, 4.0, 0.0]]
    return [
        rep, [[0.0, 0.0, 0.0], [0.0, 0.0, 8.0], [0.0, 8.0, 4.0]],
        [[t, 0.0, 0.0], rep[1], rep[2]], [rep[0], [t, 0.0, 4.0], rep[2]], [rep[0], rep[1], [t, 4.0, 0.0]],
        [[-t, 0.0, 0.0], [-t, 0.0, 4.0], [-t, 4.0, 0.0]], _SLIVER, rep[::-1],
    ]


def test_distinct_planes_keeps_every_facet_it_cannot_confirm():
    facets = np.array(_near_plane_facets())
    assert _exact_normal(*facets[0])[0] < 0 and _exact_normal(*facets[1])[0] < 0  # both face -x
    assert _exact_normal(*facets[6])[0] > 0 and _exact_normal(*facets[6])[1:] == [0, 0]  # the sliver faces +x
    # The same configuration around y = 0 and z = 0 (a cyclic shift of the axes maps
    # x = 0 to y = 0 and z = 0 and keeps orientations), where other projections collapse.
    # Facets 2 to 7 are each the only one of their oriented plane: all stay.  Of 0 and 1
    # (the same oriented plane) at least one stays; one is dropped when the other
    # represents the group (which member represents a group is not specified).
    shifted = [facets, facets[:, :, [2, 0, 1]], facets[:, :, [1, 2, 0]]]
    for group in shifted:
        keep = cm._distinct_planes([group[:, 0], group[:, 1], group[:, 2]])
        assert set(keep.tolist()) >= {2, 3, 4, 5, 6, 7} and set(keep.tolist()) & {0, 1}
    every = np.concatenate(shifted)
    keep = set(cm._distinct_planes([every[:, 0], every[:, 1], every[:, 2]]).tolist())
    for base in (0, 8, 16):
        assert keep >= {base + i for i in range(2, 8)} and keep & {base, base + 1}


# --------------------------------------------------------------------------- 2D: a convex ring, both strategies


def _cross(o, a, b) -> int:
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])


def _ccw_hull(points: np.ndarray) -> np.ndarray:
    """Strictly convex hull (monotone chain, integers), counter-clockwise from the lowest-leftmost point."""
    pts = sorted({(int(x), int(y)) for x, y in points})
    lower: list = []
    upper: list = []
    for p in pts:
        while len(lower) >= 2 and _cross(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    for p in reversed(pts):
        while len(upper) >= 2 and _cross(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    return np.array(lower[:-1] + upper[:-1], dtype=np.int64)


def _ring(count: int, radius: int) -> np.ndarray:
    """A convex polygon of integer points near a circle (times 2: edge midpoints are integers),
    with a vertex on the negative x axis (where the angle jumps from pi to -pi)."""
    ang = [2 * math.pi * i / count for i in range(count)]
    pts = np.array([(round(math.cos(t) * radius), round(math.sin(t) * radius)) for t in ang] + [(-radius - 1, 0)])
    ring = _ccw_hull(pts) * 2
    assert any((ring[:, 0] < 0) & (ring[:, 1] == 0))
    return ring


def _ring_probes(ring: np.ndarray, seed: int) -> np.ndarray:
    """Scattered integer points, the edge midpoints (on the polygon) and each one ulp beyond and
    within its edge along the outward normal's larger component, corners and corners times 3
    (on the ray from the centre through the corner) one ulp off along each axis, points on
    the negative x axis (y = 0.0 and -0.0) inside and outside, far points, the centre."""
    rng = np.random.default_rng(seed)
    a, b = ring, np.roll(ring, -1, axis=0)
    mid = (a + b) // 2
    u = b - a
    normal = np.stack([u[:, 1], -u[:, 0]], axis=1)
    nudged = []
    for e in range(len(ring)):
        k = int(np.argmax(np.abs(normal[e])))
        for step in (_up, _down):
            p = mid[e].astype(np.float64)
            p[k] = step(p[k])
            nudged.append(p)
    for v in np.vstack([ring[::3], ring[1::3] * 3]).astype(np.float64):
        for k in range(2):
            for step in (_up, _down):
                p = v.copy()
                p[k] = step(p[k])
                nudged.append(p)
    r = int(np.abs(ring).max())
    axis = [[-x, y] for x in (r // 2, r - 2, r, r + 2, 3 * r) for y in (0.0, -0.0)]
    return np.vstack([rng.integers(-r - r // 4, r + r // 4 + 1, size=(200, 2)), mid, np.array(nudged),
                      np.array(axis), ring[::5] * 3, ring[::3], [[0, 0], [1, 0]]]).astype(np.float64)


def _ring_case(seed: int, scale: float):
    ring = _ring(160, 400)
    pts = np.vstack([ring.astype(np.float64), _ring_probes(ring, seed)]) * scale
    poly = np.arange(len(ring))
    edges = np.stack([poly, np.roll(poly, -1)], axis=1)
    return pts, poly, edges


@pytest.mark.parametrize("scale", SCALES)
def test_angular_search_on_a_ring_against_integers(scale):
    pts, poly, edges = _ring_case(7, scale)
    want = _exact_outside(pts, edges, scale)
    assert 50 < len(want) < len(pts) - 200 and len(pts) * len(poly) > cm._SMALL
    res = check_containment2d(pts, poly, certified=True, center=np.zeros(2))
    assert res.outside.tolist() == want and res.ok is False and res.method == "cones"
    assert res.outside.dtype == np.int64


def test_brute_on_a_ring_against_integers():
    pts, poly, edges = _ring_case(7, 1.0)
    want = _exact_outside(pts, edges)
    for kwargs in ({"certified": False, "center": np.zeros(2)}, {"certified": True}, {}):
        res = check_containment2d(pts, poly, **kwargs)
        assert res.outside.tolist() == want and res.ok is False and res.method == "brute", kwargs


def _largest_distance(points: np.ndarray, facets: np.ndarray, outside: list[int]) -> float:
    """The largest distance of a point of ``outside`` above a facet plane (exact integer
    numerator, float division: the magnitude is a float report).  Only the integer points
    count: the others are within an ulp of the surface, far below the far points' distance."""
    corners = [points[facets[:, k]].astype(np.int64) for k in range(facets.shape[1])]
    if len(corners) == 3:
        n = np.cross(corners[1] - corners[0], corners[2] - corners[0])
    else:
        u = corners[1] - corners[0]
        n = np.stack([u[:, 1], -u[:, 0]], axis=1)
    off = np.einsum("ij,ij->i", n, corners[0])
    p = points[outside]
    p = p[np.all(p == np.round(p), axis=1)].astype(np.int64)
    height = p @ n.T - off  # exact in int64
    return float((height / np.sqrt((n * n).sum(axis=1).astype(np.float64))).max())


@pytest.mark.parametrize("dim", [2, 3])
def test_the_magnitude_is_the_largest_distance_outside(dim):
    # "Largest distance outside (float, for reporting)": the same for every strategy.
    if dim == 3:
        pts, facets, fs = _ball_case(5, 1.0)
        he = half_edges(fs, len(pts))
        runs = [check_containment3d(pts, fs, facets, certified=True, center=np.zeros(3), he=he),
                check_containment3d(pts, fs, facets, certified=False, center=np.zeros(3)),
                check_containment3d(pts, fs, facets)]
    else:
        pts, poly, facets = _ring_case(7, 1.0)
        runs = [check_containment2d(pts, poly, certified=True, center=np.zeros(2)),
                check_containment2d(pts, poly, center=np.zeros(2)), check_containment2d(pts, poly)]
    want = _exact_outside(pts, facets)
    top = _largest_distance(pts, facets, want)
    assert top > 100.0  # the far points
    for res in runs:
        assert res.magnitude == pytest.approx(top, rel=1e-12), res.method


def test_angular_search_falls_back_to_brute_force_where_corner_angles_collide():
    # A long spike pointing left: thirteen corners at x ~ -2**60 with |y| <= 6 (on the
    # parabola x = -2**60 + 512 y**2), then two far corners at x = 2**60.  Seen from the
    # centre, the thirteen lie within 6 * 2**-60 of the angle pi, so their float angles are
    # all pi (y >= 0) or -pi (y < 0): the angular guess can be off by more than the two
    # steps tried, and those points fall back to brute force (documented: method
    # "cones+brute").  Every answer is still exact.
    big = 2**60
    corners = [(-big + 512 * y * y, y) for y in range(6, -7, -1)] + [(big, -(2**48)), (big, 2**48)]
    hull = [tuple(int(v) for v in p) for p in _ccw_hull(np.array(corners, dtype=object))]
    assert sorted(hull) == sorted(corners)  # strictly convex
    ring = np.array(corners, dtype=np.float64)
    assert ring.astype(np.int64).tolist() == [list(c) for c in corners]  # exact in doubles
    assert set(np.arctan2(ring[:13, 1], ring[:13, 0]).tolist()) == {math.pi, -math.pi}
    probes = []
    for i in range(12):  # edge i joins corner i (y = 6 - i) and corner i + 1
        (x0, y0), (x1, y1) = corners[i], corners[i + 1]
        mx, my = float((x0 + x1) // 2), (y0 + y1) / 2  # on the edge (x0 + x1 is even)
        probes += [(mx, my), (mx, _up(my)), (mx, _down(my)), (mx, my + 0.25), (mx, my - 0.25)]
    rng = np.random.default_rng(11)
    deep = rng.integers(-(2**40), 2**40, size=(3500, 2))  # inside the inscribed disc: settled at once
    pts = np.vstack([ring, np.array(probes), deep.astype(np.float64)])
    poly = np.arange(len(ring))
    edges = np.stack([poly, np.roll(poly, -1)], axis=1)
    want = _exact_outside(pts, edges)
    # By hand: the edges are nearly horizontal; the upper arm's outside is up, the lower
    # arm's down (edge 6 joins y = 0 and y = -1): one ulp or 0.25 beyond, never on the edge.
    assert want == [15 + 5 * i + j for i in range(12) for j in ((1, 3) if i < 6 else (2, 4))]
    assert len(pts) * len(poly) > cm._SMALL
    res = check_containment2d(pts, poly, certified=True, center=np.zeros(2))
    assert res.outside.tolist() == want and res.ok is False and res.method == "cones+brute"


# --------------------------------------------------------------------------- points settled without a cone


def test_every_point_deep_or_a_corner_returns_the_empty_answer():
    # Large enough for the cones, but every point is a corner of the certified surface or
    # inside the inscribed ball around the centre (the ball's radius here is above 200;
    # the deep points are within 50 * sqrt(3) of it): nothing is outside.
    shell, tri = _ball_surface()
    rng = np.random.default_rng(2)
    pts = np.vstack([shell, rng.integers(-50, 51, size=(400, 3))]).astype(np.float64)
    fs = FaceSet.from_polygons(tri.tolist())
    assert _exact_outside(pts, tri) == [] and len(pts) * len(tri) > cm._SMALL
    he = half_edges(fs, len(pts))
    res = check_containment3d(pts, fs, tri, certified=True, center=np.zeros(3), he=he)
    assert res.ok is True and res.method == "cones" and res.magnitude == 0.0
    assert res.outside.dtype == np.int64 and res.outside.shape == (0,)
    # One point inside the surface but outside the ball: the same answer through the cones.
    pts[-1] = [0.0, 0.0, 233.0]  # the ball's radius is about 230.4, the surface is at z = 235.1 there
    assert _exact_outside(pts, tri) == []
    for k in (1, 3):  # with three candidates, the candidate rounds end once every point is located
        res = check_containment3d(pts, fs, tri, certified=True, center=np.zeros(3), he=he, k=k)
        assert res.ok is True and res.method == "cones" and res.magnitude == 0.0
        assert res.outside.dtype == np.int64 and res.outside.shape == (0,)
    # 2D: the ring's corners and points near its centre.
    ring = _ring(160, 400)
    pts2 = np.vstack([ring, rng.integers(-200, 201, size=(400, 2))]).astype(np.float64)
    poly = np.arange(len(ring))
    for extra in ([], [[0.0, 799.5]]):  # all settled at once; one inside beyond the disc (radius ~799.3)
        p = np.vstack([pts2] + ([np.array(extra)] if extra else []))
        assert _exact_outside(p, np.stack([poly, np.roll(poly, -1)], axis=1)) == []
        res = check_containment2d(p, poly, certified=True, center=np.zeros(2))
        assert res.ok is True and res.method == "cones" and res.magnitude == 0.0
        assert res.outside.dtype == np.int64 and res.outside.shape == (0,)


def _flat_octahedron(width: float, height: float) -> tuple[np.ndarray, np.ndarray]:
    """Corners (+-width, 0, 0), (0, +-width, 0), (0, 0, +-height), eight outward triangles."""
    pts = np.array([[width, 0, 0], [-width, 0, 0], [0, width, 0], [0, -width, 0], [0, 0, height], [0, 0, -height]])
    tri = []
    for x in (0, 1):
        for y in (2, 3):
            for z in (4, 5):
                t = [x, y, z]
                n = _exact_normal(*pts[t])
                a = [Fraction(float(v)) for v in pts[x]]
                tri.append(t if sum(p * q for p, q in zip(n, a)) > 0 else t[::-1])  # the origin below
    return pts, np.array(tri)


def test_a_point_whose_squared_offset_underflows_is_not_taken_as_deep():
    # A flat octahedron 2 wide and 2**-599 thick: the inscribed ball around the origin has
    # a radius of about 2**-600.  A point 2**-598 above the origin is outside (above the
    # top corner), but the square of its offset underflows to 0, so its float distance from
    # the centre is 0: only the absolute term added to that distance (2**-500) keeps it out
    # of the ball.  Thousands of copies of the centre make the input large enough for the
    # ball to be used at all.
    corners, tri = _flat_octahedron(1.0, 2.0**-600)
    assert 0 < inner_radius([corners[tri[:, k]] for k in range(3)], np.zeros(3)) < 2.0**-599
    probes = np.array([[0.0, 0.0, 2.0**-598], [0.0, 0.0, 2.0**-601], [0.0, 0.0, -(2.0**-598)], [2.0**-598, 0.0, 0.0]])
    want = _exact_outside(np.vstack([corners, probes]), tri, 2.0**-600)
    assert want == [6, 8]  # above the top corner and below the bottom one; the others inside
    pts = np.vstack([corners, probes, np.zeros((7000, 3))])
    assert len(pts) * len(tri) > cm._SMALL
    fs = FaceSet.from_polygons(tri.tolist())
    he = half_edges(fs, len(pts))
    for kwargs, method in (({"certified": True, "he": he}, "cones"), ({}, "brute")):
        res = check_containment3d(pts, fs, tri, center=np.zeros(3), **kwargs)
        assert res.outside.tolist() == want and res.method == method


# --------------------------------------------------------------------------- helpers, chunks and fallbacks


def test_unit_rows_scale_rows_to_length_one_without_overflow_or_underflow():
    # "Rows scaled to unit length, for candidate search only (no overflow at 1e300; zero
    # rows stay zero)"; tiny rows, whose squares underflow, too.
    tiny = 2.0**-1060  # 3 and 4 times it are exact subnormals
    v = np.array([[3.0, 4.0, 0.0], [3e300, 0.0, -4e300], [0.0, 3 * tiny, 4 * tiny], [0.0, 0.0, 0.0],
                  [0.0, 0.0, -2.0], [5e-324, 0.0, 0.0], [1.0, 1.0, 1.0]])
    r = 1 / math.sqrt(3)
    want = [[0.6, 0.8, 0.0], [0.6, 0.0, -0.8], [0.0, 0.6, 0.8], [0.0, 0.0, 0.0], [0.0, 0.0, -1.0], [1.0, 0.0, 0.0], [r, r, r]]
    got = cm._unit_rows(v)
    assert got.dtype == np.float64 and got.shape == v.shape
    assert np.abs(got - np.array(want)).max() < 1e-15


def test_the_default_is_not_certified():
    # certified defaults to False: with a centre (and half-edges) but no certificate, brute force.
    pts, tri, fs = _ball_case(5, 1.0)
    res = check_containment3d(pts, fs, tri, center=np.zeros(3), he=half_edges(fs, len(pts)))
    assert res.method == "brute" and res.outside.tolist() == _exact_outside(pts, tri)
    pts2, poly, edges = _ring_case(7, 1.0)
    res = check_containment2d(pts2, poly, center=np.zeros(2))
    assert res.method == "brute" and res.outside.tolist() == _exact_outside(pts2, edges)


@pytest.mark.parametrize("patch", [{"_CHUNK": 3}, {"_CHUNK": 5000}, {"_CONE_CHUNK": 2}, {"_CONE_CHUNK": 7},
                                   {"_WALK_STEPS": 0}, {"_WALK_STEPS": 1}])
def test_chunk_sizes_and_walk_length_leave_the_answer_exact(monkeypatch, patch):
    # Documented: brute force works in chunks, the cones in chunks of cone edges, and a
    # point the walk does not locate falls back to brute force ("cones+brute").  Small
    # chunks (one candidate, or one (point, facet) pair, at a time) and short walks must
    # give the same exact answer.
    for name, value in patch.items():
        monkeypatch.setattr(cm, name, value)
    pts, tri, fs = _ball_case(5, 1.0)
    want = _exact_outside(pts, tri)
    he = half_edges(fs, len(pts))
    res = check_containment3d(pts, fs, tri, certified=True, center=np.zeros(3), he=he)
    assert res.outside.tolist() == want and res.ok is False
    if patch.get("_WALK_STEPS") == 0:
        assert res.method == "cones+brute"  # some points are not in their first candidate's cone
    else:
        assert res.method.startswith("cones")
    if patch.get("_CHUNK") == 3:
        tet = np.vstack([_TET, _tet_probes(1.0)])  # 4 facets: chunks of max(1, 3 // 4) = 1 candidate
        res = check_containment3d(tet, FaceSet.from_polygons(_TET_FACES), np.array(_TET_FACES))
        assert res.outside.tolist() == [5, 7, 10, 13, 14] and res.method == "brute"
    elif "_CHUNK" in patch:  # 25 (3D) and 31 (2D) candidates at a time
        res = check_containment3d(pts, fs, tri)
        assert res.outside.tolist() == want and res.method == "brute"
        pts2, poly, edges = _ring_case(7, 1.0)
        res = check_containment2d(pts2, poly)
        assert res.outside.tolist() == _exact_outside(pts2, edges) and res.method == "brute"


# --------------------------------------------------------------------------- overflow in the float filter


def _spike() -> tuple[np.ndarray, list[list[int]]]:
    """A tetrahedron a, b, c, d whose face (a, b, c) has the normal (4, -2, -2) * 2**600, and
    p = d / 2 on its edge a-d, where p . normal is (4 - 4 (1 + 2**-52)) * 2**1024: the
    first term of that sum alone overflows (2**1024), the exact sum is -2**972.  The last
    point, d * 2**-1400, also on the edge a-d, keeps the checker from rescaling the input
    (scaled by 2**-424 it would underflow)."""
    t = 2.0**300
    a, b, c = np.zeros(3), np.array([1.0, 2.0, 0.0]) * t, np.array([1.0, 0.0, 2.0]) * t
    p = np.array([2.0**422, 2.0**422 * (1 + 2.0**-52), 2.0**422 * (1 + 2.0**-52)])
    d = 2 * p
    pts = np.array([a, b, c, d, p, d * 2.0**-700 * 2.0**-700])
    faces = [[0, 1, 2], [3, 1, 0], [0, 2, 3], [3, 2, 1]]
    return pts, faces


def _exact_sides(pts: np.ndarray, faces, i: int) -> list[int]:
    out = []
    for f in faces:
        n = _exact_normal(*pts[f])
        x, a = ([Fraction(float(v)) for v in pts[k]] for k in (i, f[0]))
        h = sum(n[k] * (x[k] - a[k]) for k in range(3))
        out.append((h > 0) - (h < 0))
    return out


def test_an_overflowed_float_distance_decides_nothing():
    # Regression: the float filter took an s that overflowed to +inf (or -inf) for decided,
    # though an intermediate overflow says nothing about the exact sign (here p . n has
    # one term of 2**1024 and an exact value of -2**972; whether a dot product overflows
    # depends on the order of its terms, so the old answer depended on the BLAS kernel and
    # on how many candidates were in the chunk).  Now a non-finite s goes to the exact test.
    pts, faces = _spike()
    for i in range(len(pts)):  # every point on or below every face, exactly: nothing is outside
        assert max(_exact_sides(pts, faces, i)) == 0
    assert _exact_sides(pts, faces, 4) == [-1, 0, 0, -1]
    tri = np.array(faces)
    planes = [pts[tri[:, 0]], pts[tri[:, 1]], pts[tri[:, 2]]]
    for candidates in ([4], [3], [3, 4], [0, 1, 2, 3, 4, 5], [4, 4, 4]):
        got, worst = cm._brute(pts, planes, tri, np.array(candidates))
        assert got.tolist() == [] and worst == 0.0, candidates
    fs = FaceSet.from_polygons(faces)
    for kwargs in ({}, {"certified": True, "center": pts[4] / 2, "he": half_edges(fs, len(pts))}):
        res = check_containment3d(pts, fs, tri, **kwargs)
        assert res.ok is True and res.outside.tolist() == []


def test_the_overflow_regression_through_the_public_check():
    from hullstress.checker import check

    pts, faces = _spike()
    v = check(pts, faces)
    assert v.containment is True and "containment" not in v.failed_checks, v.detail


def test_row_max_and_row_sum():
    # "Largest entry of each row" and "Sum of each row, left to right", for the 2- and
    # 3-column arrays the module uses (small integers: every sum is exact).
    v = np.array([[5.0, -1.0, 2.0], [-3.0, 7.0, 1.0], [0.0, -2.0, 9.0], [-4.0, -6.0, -5.0]])
    assert cm._row_max(v).tolist() == [5.0, 7.0, 9.0, -4.0]
    assert cm._row_sum(v).tolist() == [6.0, 5.0, 7.0, -15.0]
    assert cm._row_max(v[:, 1:]).tolist() == [2.0, 7.0, 9.0, -5.0]
    assert cm._row_sum(v[:, 1:]).tolist() == [1.0, 8.0, 7.0, -11.0]
    assert v.tolist()[0] == [5.0, -1.0, 2.0]  # the input is left alone


# --------------------------------------------------------------------------- the float filter's bound, at its edges


def _both_sides(b, c, probes) -> tuple[np.ndarray, FaceSet, np.ndarray]:
    """Points 0, b, c and ``probes``; the facets (0, b, c) and (0, c, b): every point off
    their common plane is outside one of them, every point on it outside neither."""
    pts = np.vstack([np.zeros(3), b, c, probes])
    tri = np.array([[0, 1, 2], [0, 2, 1]])
    return pts, FaceSet.from_polygons(tri.tolist()), tri


def test_a_sliver_whose_float_normal_points_the_wrong_way():
    # _SLIVER faces +x exactly, but its float normal points to -x: every point with x > 0
    # is exactly outside it, though its float distance says inside.  The normal's
    # rounding error (the bound's 8 eps term of the cross product's two products) is what
    # sends them to the exact test.
    sliver = np.array(_SLIVER)
    probes = np.array([[1.0, 0.0, 0.0], [2.0**-30, 5.0, -7.0], [3.0, -1e5, 2e4], [0.0, 9.0, 9.0], [-1.0, 0.0, 0.0]])
    pts, fs, tri = _both_sides(sliver[1] - sliver[0], sliver[2] - sliver[0], probes)
    pts[:3] = sliver
    one = tri[:1]
    want = [3, 4, 5]  # x > 0: outside the sliver (exact normal +x)
    assert _exact_normal(*sliver)[0] > 0 and _exact_normal(*sliver)[1:] == [0, 0]
    assert cm._brute(pts, [pts[one[:, 0]], pts[one[:, 1]], pts[one[:, 2]]], one, np.arange(3, 8))[0].tolist() == want
    res = check_containment3d(pts, FaceSet.from_polygons(one.tolist()), one)
    assert res.outside.tolist() == want and res.method == "brute"
    # With the sliver reversed too, every point off the plane x = 0 is outside.
    assert check_containment3d(pts, fs, tri).outside.tolist() == [3, 4, 5, 7]


def test_facets_whose_float_normal_underflows():
    # A facet 2**-600 across at the origin: its normal (2**-1200) underflows to 0, so every
    # float distance is 0; with a point at distance 1 in the same check, the bound must
    # still send them all to the exact test.
    t = 2.0**-600
    probes = np.array([[0.0, 0.0, 1.0], [0.0, 0.0, -1.0], [5.0, 3.0, 2.0**-1074], [3.0, 3.0, 0.0], [t, t, -t]])
    pts = np.vstack([[[0.0, 0.0, 0.0], [t, 0.0, 0.0], [0.0, t, 0.0]], probes])
    tri = np.array([[0, 1, 2]])  # faces +z
    assert _exact_outside(pts, tri, t) == [3, 5]  # z > 0
    assert check_containment3d(pts, FaceSet.from_polygons([[0, 1, 2]]), tri).outside.tolist() == [3, 5]
    # 2D: an edge 3 * 2**-1074 long (a subnormal normal); its float distances underflow.
    e = 3 * 5e-324
    pts2 = np.array([[0.0, 0.0], [e, 0.0], [0.0, -(2.0**-60)], [0.0, 2.0**-60], [5.0, 0.0], [0.0, -1.0]])
    edges = np.array([[0, 1], [1, 0]])
    assert _exact_outside(pts2, edges, 5e-324) == [2, 3, 5]
    assert check_containment2d(pts2, np.array([0, 1])).outside.tolist() == [2, 3, 5]


# Found by a search, kept for their digits: b and c with full 53-bit mantissas.
_SUB_B = [1.6802073719816204e-162, 2.1677051232807388e-162, -1.271595394990012e-162]
_SUB_C = [-1.581855658913659e-162, 2.0312709659354787e-162, 1.5661548550656842e-162]
_UNDER_B = [-1.6747424035743034e-23, -1.4074176334134587e-23, 1.4959583080265745e-23]
_UNDER_C = [1.382523170789076e-23, 2.0437724330939907e-23, -1.7567838663841722e-23]


@pytest.mark.parametrize(("b", "c", "powers"), [(_SUB_B, _SUB_C, [600, 650, 690, 700, 720]),
                                                (_UNDER_B, _UNDER_C, [-825, -830, -840, -850])])
def test_points_on_a_facet_plane_where_the_products_lose_their_digits(b, c, powers):
    # Points 2**k b and 2**k c lie exactly on the plane through the origin, b and c (a
    # power of two scales exactly), so neither of the two opposite facets has them outside.
    # First b and c about 2**-537 (the normal, about 2**-1074, is a subnormal with a few
    # digits) and the points about 2**150 away; then b and c about 2**-75 and the points
    # about 2**-900 (their products with the normal are subnormals).  The float distances
    # are a few units of the last subnormal digit times the points' size, not 0: only the
    # absolute terms of the bound (2**-1000) send them to the exact test.
    b, c = np.array(b), np.array(c)
    probes = np.array([x * 2.0**k for k in powers for x in (b, c)])
    pts, fs, tri = _both_sides(b, c, probes)
    res = check_containment3d(pts, fs, tri)
    assert res.outside.tolist() == [] and res.ok is True
    # The probes alone (pmax is then theirs, not the facet's).
    got, _ = cm._brute(pts, [pts[tri[:, 0]], pts[tri[:, 1]], pts[tri[:, 2]]], tri, np.arange(3, len(pts)))
    assert got.tolist() == []


@pytest.mark.parametrize("scale", [1.0, 2.0**40])
def test_a_facet_collinear_up_to_rounding(scale):
    # b and c were computed in floats as a + 1000 d and a + 8.71 d (d a direction), so the
    # facet is collinear up to their rounding: its exact normal is tiny, and the rounding
    # errors of the float cross product, about eps times the products of the edge
    # vectors' components, decide the float normal's direction.  The bound's term for them (8 eps times those products)
    # sends every point near the facet to the exact test; the signs below are exact.
    a = [-0.8783945740838879, 0.11119223384144683, -0.45709679093979694]
    b = [758.4239520957603, -871.4599331417766, 357.90596925179017]
    c = [5.73807205269756, -7.4835706286808, 2.6656345915483257]
    probes = [[-0.138, -0.315, -0.251], [-0.323, 0.543, 0.374], [-0.309, -0.258, -0.046], [-0.313, 1.087, 0.515],
              [-0.113, 0.937, -0.041], [-1.138, 0.323, -0.502], [-0.278, -0.45, -0.011], [-1.729, -0.874, -1.098]]
    pts = np.array([a, b, c, *probes]) * scale  # 2**40: the products of the edge vectors near 2**93
    want = [i for i in range(3, len(pts)) if _exact_sides(pts, [[0, 1, 2]], i) == [1]]
    assert 0 < len(want) < len(probes)
    tri = np.array([[0, 1, 2]])
    assert check_containment3d(pts, FaceSet.from_polygons([[0, 1, 2]]), tri).outside.tolist() == want


# --------------------------------------------------------------------------- which strategy, and what is skipped


def test_cones_near_the_top_of_the_double_range():
    # At 2**1015 the corners reach 1.05e308: the sum of a facet's three corners (for its
    # direction from the centre) overflows, and the float filter decides nothing; the
    # answer is still exact, and no overflow warning escapes.
    shell, tri = _ball_surface()
    probes = _ball_probes(shell, tri, 5)
    scale = 2.0**1015
    pts = np.vstack([shell, probes[np.abs(probes).max(axis=1) <= 300]]).astype(np.float64) * scale
    fs = FaceSet.from_polygons(tri.tolist())
    want = _exact_outside(pts, tri, scale)
    assert len(want) > 50 and len(pts) * len(tri) > cm._SMALL
    res = check_containment3d(pts, fs, tri, certified=True, center=np.zeros(3), he=half_edges(fs, len(pts)))
    assert res.outside.tolist() == want and res.method.startswith("cones")
    # At 2**1016, with the centre at x = -216 * 2**1016 (inside: the inscribed radius is
    # about 230 * 2**1016), the offsets of the points on the far side overflow.
    scale = 2.0**1016
    pts = np.vstack([shell, probes[np.abs(probes).max(axis=1) <= 255]]).astype(np.float64) * scale
    centre = np.array([-216.0, 0.0, 0.0]) * scale
    want = _exact_outside(pts, tri, scale)
    assert _exact_outside(np.vstack([pts, centre]), tri, scale) == want  # the centre is not outside
    assert len(want) > 50 and float(pts[:, 0].max()) - float(centre[0]) == math.inf
    res = check_containment3d(pts, fs, tri, certified=True, center=centre, he=half_edges(fs, len(pts)))
    assert res.outside.tolist() == want and res.method.startswith("cones")


def test_cones_around_a_centre_off_the_origin():
    # The same surfaces moved by an integer offset, the centre with them.
    shift = np.array([1000, -2000, 500])
    pts, tri, fs = _ball_case(5, 1.0)
    pts = pts + shift
    want = _exact_outside(pts, tri)
    for k in (1, 3):
        res = check_containment3d(pts, fs, tri, certified=True, center=shift.astype(np.float64),
                                  he=half_edges(fs, len(pts)), k=k)
        assert res.outside.tolist() == want and res.method == "cones"
    pts2, poly, edges = _ring_case(7, 1.0)
    pts2 = pts2 + shift[:2]
    res = check_containment2d(pts2, poly, certified=True, center=shift[:2].astype(np.float64))
    assert res.outside.tolist() == _exact_outside(pts2, edges) and res.method == "cones"
    # The polygon listed from other corners (the first no longer the one of least angle).
    for start in (1, 40, 100):
        res = check_containment2d(pts2, np.roll(poly, -start), certified=True, center=shift[:2].astype(np.float64))
        assert res.outside.tolist() == _exact_outside(pts2, edges) and res.method == "cones", start


def test_small_inputs_use_brute_force_even_when_certified():
    # "Below this many point-facet entries, brute force": a certified tetrahedron with its
    # centre and half-edges, and a certified square.  Its own corners are skipped there
    # (they lie on the certified surface), the other points decided exactly.
    pts = np.vstack([_TET, _tet_probes(1.0)])
    fs = FaceSet.from_polygons(_TET_FACES)
    tri = np.array(_TET_FACES)
    he = half_edges(fs, len(pts))
    res = check_containment3d(pts, fs, tri, certified=True, center=np.array([1.0, 1.0, 1.0]), he=he)
    assert res.outside.tolist() == [5, 7, 10, 13, 14] and res.ok is False and res.method == "brute"
    inside = pts[[0, 1, 2, 3, 4, 6, 11]]  # the corners, a point on a face, one ulp within it, the centre
    res = check_containment3d(inside, fs, tri, certified=True, center=np.array([1.0, 1.0, 1.0]), he=he)
    assert res.outside.tolist() == [] and res.ok is True and res.method == "brute" and res.magnitude == 0.0
    assert res.outside.dtype == np.int64
    square = np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [0.0, 4.0], [2.0, 2.0], [4.0, 1.0], [_up(4.0), 1.0]])
    res = check_containment2d(square, np.arange(4), certified=True, center=np.array([2.0, 2.0]))
    assert res.outside.tolist() == [6] and res.ok is False and res.method == "brute"
    res = check_containment2d(square[:6], np.arange(4), certified=True, center=np.array([2.0, 2.0]))
    assert res.outside.tolist() == [] and res.ok is True and res.method == "brute" and res.outside.dtype == np.int64


def test_the_corners_of_an_uncertified_surface_are_checked():
    # Only a certified surface's own corners may be skipped: here corner 4 is a corner of
    # the extra facet (4, 1, 2) and lies beyond the face x + y + z = 4, so it is outside,
    # centre or not.
    pts = np.vstack([_TET, [[3.0, 3.0, 3.0]]])
    faces = _TET_FACES + [[4, 1, 2]]
    fs = FaceSet.from_polygons(faces)
    tri = np.array(faces)
    assert _exact_outside(pts, tri) == [4]
    for kwargs in ({}, {"center": np.array([0.5, 0.5, 0.5])}, {"certified": False, "center": np.array([0.5, 0.5, 0.5])}):
        res = check_containment3d(pts, fs, tri, **kwargs)
        assert res.outside.tolist() == [4] and res.method == "brute", kwargs
    # 2D: the polygon (0, 0), (4, 0), (4, 4), (2, 1), (0, 4) has a dent at (2, 1); by hand,
    # corners 0 and 4 are right of the line from (4, 4) to (2, 1), corners 1 and 2 right of
    # the line from (2, 1) to (0, 4).
    poly2 = np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [2.0, 1.0], [0.0, 4.0]])
    ring = np.arange(5)
    assert _exact_outside(poly2, np.stack([ring, np.roll(ring, -1)], axis=1)) == [0, 1, 2, 4]
    for kwargs in ({}, {"center": np.array([1.0, 0.5])}, {"certified": False, "center": np.array([1.0, 0.5])}):
        res = check_containment2d(poly2, ring, **kwargs)
        assert res.outside.tolist() == [0, 1, 2, 4] and res.method == "brute", kwargs


def test_degenerate_faces_and_zero_length_edges_are_skipped():
    # Documented: a face without a plane (a -1 row) is skipped, and so is a zero-length
    # edge; the other facets still decide.  Here the tetrahedron has an extra degenerate face.
    pts = np.vstack([_TET, _tet_probes(1.0)])
    faces = _TET_FACES + [[0, 0, 1]]
    plane = np.vstack([np.array(_TET_FACES), [[-1, -1, -1]]])
    res = check_containment3d(pts, FaceSet.from_polygons(faces), plane)
    assert res.outside.tolist() == [5, 7, 10, 13, 14] and res.method == "brute"
    # 2D: a square whose corner 1 appears twice (indices 1 and 4 have its coordinates), with
    # a point just outside each of its four axis-aligned edges, and one inside.
    square = np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [0.0, 4.0], [4.0, 0.0],
                       [2.0, -1.0], [5.0, 2.0], [2.0, 4.5], [-0.5, 2.0], [2.0, 2.0]])
    poly = np.array([0, 1, 4, 2, 3])  # 1 -> 4 has length 0
    res = check_containment2d(square, poly)
    assert res.outside.tolist() == [5, 6, 7, 8] and res.method == "brute"
    # Only a zero-length edge: no edge at all, nothing outside.
    res = check_containment2d(square, np.array([1, 4]))
    assert res.outside.tolist() == [] and res.ok is True


def test_a_certified_triangle_uses_the_angular_search(monkeypatch):
    # Three edges are enough for the angular search (the threshold lowered, so that a small
    # input takes it); an uncertified one is brute force.
    monkeypatch.setattr(cm, "_SMALL", 0)
    tri = np.array([[0.0, 0.0], [8.0, 0.0], [0.0, 8.0], [1.0, 1.0], [4.0, 4.0], [_up(4.0), 4.0], [9.0, -1.0],
                    [-1.0, 9.0], [2.0, 0.5], [0.5, 2.0], [8.0, 8.0]])
    poly = np.arange(3)
    want = _exact_outside(tri, np.stack([poly, np.roll(poly, -1)], axis=1))
    assert want == [5, 6, 7, 10]
    res = check_containment2d(tri, poly, certified=True, center=np.array([2.0, 2.0]))
    assert res.outside.tolist() == want and res.method == "cones"
    res = check_containment2d(tri, poly, certified=False, center=np.array([2.0, 2.0]))
    assert res.outside.tolist() == want and res.method == "brute"


def test_angular_search_takes_two_steps_back_where_three_corner_angles_collide():
    # As above with five corners at x ~ -2**60, |y| <= 2: three share the float angle pi,
    # two share -pi, so the guess for a point near them is off by up to two edges, which
    # the search's steps (0, -1, 1, -2, 2) still reach: no fallback (method "cones").
    big = 2**60
    corners = [(-big + 512 * y * y, y) for y in range(2, -3, -1)] + [(big, -(2**48)), (big, 2**48)]
    hull = [tuple(int(v) for v in p) for p in _ccw_hull(np.array(corners, dtype=object))]
    assert sorted(hull) == sorted(corners)  # strictly convex
    ring = np.array(corners, dtype=np.float64)
    assert np.arctan2(ring[:5, 1], ring[:5, 0]).tolist() == [math.pi] * 3 + [-math.pi] * 2
    probes = []
    for i in range(4):  # the edges between the five corners
        (x0, y0), (x1, y1) = corners[i], corners[i + 1]
        mx, my = float((x0 + x1) // 2), (y0 + y1) / 2
        probes += [(mx, my), (mx, _up(my)), (mx, _down(my)), (mx, my + 0.25), (mx, my - 0.25)]
    deep = np.random.default_rng(12).integers(-(2**40), 2**40, size=(7200, 2))
    pts = np.vstack([ring, np.array(probes), deep.astype(np.float64)])
    poly = np.arange(len(ring))
    want = _exact_outside(pts, np.stack([poly, np.roll(poly, -1)], axis=1))
    assert want == [7 + 5 * i + j for i in range(4) for j in ((1, 3) if i < 2 else (2, 4))]
    assert len(pts) * len(poly) > cm._SMALL
    res = check_containment2d(pts, poly, certified=True, center=np.zeros(2))
    assert res.outside.tolist() == want and res.method == "cones"


def _centroid_rays(shift) -> tuple[np.ndarray, np.ndarray, FaceSet]:
    """The ball surface moved by ``shift``, its corners, and for every facet the point
    centre + 3 (centroid - centre): outside, on the ray from the centre through the facet's
    centroid (strictly inside that facet's cone, and in the direction of its own centroid)."""
    shell, tri = _ball_surface()
    a, b, c = shell[tri[:, 0]], shell[tri[:, 1]], shell[tri[:, 2]]
    rays = (a + b + c) // 3 * 3  # the centroids are integers (the corners are multiples of 6)
    pts = (np.vstack([shell, rays]) + shift).astype(np.float64)
    return pts, tri, FaceSet.from_polygons(tri.tolist())


@pytest.mark.parametrize("shift", [(0, 0, 0), (1000, -2000, 500)])
def test_points_on_their_facets_centroid_ray_need_no_walk(monkeypatch, shift):
    # Each probe's direction from the centre is its own facet's centroid direction, so the
    # k-d tree's first candidate is that facet and its cone contains the probe: with the
    # walk switched off, every point is still located by the candidates (method "cones").
    monkeypatch.setattr(cm, "_WALK_STEPS", 0)
    pts, tri, fs = _centroid_rays(shift)
    want = list(range(100, len(pts)))
    assert _exact_outside(pts, tri) == want and len(pts) * len(tri) > cm._SMALL
    res = check_containment3d(pts, fs, tri, certified=True, center=np.array(shift, dtype=np.float64),
                              he=half_edges(fs, len(pts)))
    assert res.outside.tolist() == want and res.method == "cones"


def test_points_in_the_inscribed_ball_need_no_cone(monkeypatch):
    # Points within the inscribed ball are settled at once, wherever their direction
    # points: with the walk switched off, the centroid-ray probes and a hundred points near
    # the centre, in all directions, give the method "cones" (no fallback).
    monkeypatch.setattr(cm, "_WALK_STEPS", 0)
    pts, tri, fs = _centroid_rays((0, 0, 0))
    rng = np.random.default_rng(4)
    d = rng.normal(size=(100, 3))
    near = d / np.linalg.norm(d, axis=1)[:, None] * rng.uniform(20, 150, size=(100, 1))
    pts = np.vstack([pts, near])
    want = list(range(100, 100 + len(tri)))
    assert _exact_outside(pts, tri) == want  # the near points are inside (radius < 230)
    res = check_containment3d(pts, fs, tri, certified=True, center=np.zeros(3), he=half_edges(fs, len(pts)))
    assert res.outside.tolist() == want and res.method == "cones"


def test_in_cones_reports_a_separating_half_edge_or_minus_one():
    # Documented: per (point, face) pair, whether the point is in the face's closed cone,
    # and one half-edge whose plane separates it from the cone (-1 when inside).
    pts, tri, fs = _centroid_rays((0, 0, 0))
    he = half_edges(fs, len(pts))
    cones = cm._cone_planes(pts, np.zeros(3), he, float(np.abs(pts).max()))
    probes = np.arange(100, len(pts))
    own = probes - 100  # each probe's own facet: inside its cone
    other = (own + 1) % len(tri)  # another facet: outside its cone
    for cand, inside_want in ((own, True), (other, False)):
        inside, exit_edge = cm._in_cones(pts, np.zeros(3), he, fs, probes, cand, cones)
        assert inside.tolist() == [inside_want] * len(probes)
        if inside_want:
            assert exit_edge.tolist() == [-1] * len(probes)
        else:
            assert (he.face[exit_edge] == cand).all()  # a half-edge of the candidate face
            # The probe is strictly on the outer side of its cone plane (centre, src, dst):
            # below that oriented plane, as the cone's inside is above it, exactly.
            for e, q in zip(exit_edge.tolist(), probes.tolist()):
                assert _exact_sides(np.vstack([pts, np.zeros(3)]), [[len(pts), he.src[e], he.dst[e]]], q) == [-1]


@pytest.mark.parametrize("dim", [2, 3])
def test_brute_force_up_to_small_entries(monkeypatch, dim):
    # _SMALL is documented as the most point-facet entries brute force takes: at exactly that
    # many, brute force; at one more, the cones (the threshold lowered to this input's size).
    if dim == 3:
        pts = np.vstack([_TET, _tet_probes(1.0)])
        fs = FaceSet.from_polygons(_TET_FACES)
        kwargs = {"certified": True, "center": np.array([1.0, 1.0, 1.0]), "he": half_edges(fs, len(pts))}
        run = lambda: check_containment3d(pts, fs, np.array(_TET_FACES), **kwargs)  # noqa: E731
        entries, want = len(pts) * 4, [5, 7, 10, 13, 14]
    else:
        pts = np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [0.0, 4.0], [2.0, 2.0], [4.0, 1.0], [_up(4.0), 1.0]])
        run = lambda: check_containment2d(pts, np.arange(4), certified=True, center=np.array([2.0, 2.0]))  # noqa: E731
        entries, want = len(pts) * 4, [6]
    for small, method in ((entries, "brute"), (entries - 1, "cones")):
        monkeypatch.setattr(cm, "_SMALL", small)
        res = run()
        assert res.outside.tolist() == want and res.method == method, small


# --------------------------------------------------------------------------- undecided entries of points already outside


def _lattice_with_a_wrong_hull() -> tuple[np.ndarray, np.ndarray]:
    """Integer points on the plane z = 0 and two layers above it, and the outward hull of a few of them.

    Many points lie exactly on facet planes (float distance 0: undecided) and
    are outside another facet by far: the entries the exact stages skip.
    """
    g = np.arange(6, dtype=np.float64)
    plane = np.array([[x, y, 0.0] for x in g for y in g])
    above = np.array([[x, y, z] for x in (1.0, 3.0) for y in (1.0, 4.0) for z in (1.0, 2.0)])
    pts = np.vstack([plane, above])
    kept = [0, 2, 12, 14, 36, 39]  # (0,0,0), (0,2,0), (2,0,0), (2,2,0) and two points above
    hull = ConvexHull(pts[kept])
    facets = np.array(kept)[hull.simplices]
    for row, eq in zip(facets, hull.equations):  # outward: the normal (b - a) x (c - a) along Qhull's
        a, b, c = pts[row]
        if np.dot(np.cross(b - a, c - a), eq[:3]) < 0:
            row[[1, 2]] = row[[2, 1]]
    return pts, facets


def test_brute_skips_only_entries_that_cannot_change_its_answer(monkeypatch):
    pts, facets = _lattice_with_a_wrong_hull()
    planes = [pts[facets[:, k]] for k in range(3)]
    candidates = np.arange(len(pts))
    seen: list[tuple[int, int]] = []
    still_open = cm._still_open

    def counting(gi, gf, *args):
        kept = still_open(gi, gf, *args)
        seen.append((len(gi), len(kept[0])))
        return kept

    monkeypatch.setattr(cm, "_still_open", counting)
    outside, worst = cm._brute(pts, planes, facets, candidates)
    monkeypatch.setattr(cm, "_still_open", lambda gi, gf, *args: (gi, gf))
    every_outside, every_worst = cm._brute(pts, planes, facets, candidates)
    assert sum(before - after for before, after in seen) > 0  # undecided entries were skipped
    assert outside.tolist() == every_outside.tolist() == _exact_outside(pts, facets)
    assert worst == every_worst > 0


def _open_facets(gi, gf, outside, s, norm, worst):
    with np.errstate(all="raise"):  # the rule keeps its own floating-point state
        kept = cm._still_open(np.array(gi), np.array(gf), np.array(outside), np.array(s, dtype=float),
                              np.array(norm, dtype=float), worst)
    return list(zip(kept[0].tolist(), kept[1].tolist()))


def test_an_undecided_entry_farther_than_every_decided_one_is_still_decided():
    # Point 0 is outside facet 0 (decided in floats) at distance 4 / 2 = 2.  Its undecided entry
    # on facet 1 matters only if farther: 12 / 4 = 3 is, 6 / 4 = 1.5 is not; an earlier chunk's
    # distance of 5 outdoes both.
    norm = [2.0, 4.0]
    assert _open_facets([0], [1], [[True, False]], [[4.0, 12.0]], norm, 0.0) == [(0, 1)]
    assert _open_facets([0], [1], [[True, False]], [[4.0, 6.0]], norm, 0.0) == []
    assert _open_facets([0], [1], [[True, False]], [[4.0, 12.0]], norm, 5.0) == []
    # Only decided outside entries count: facet 1's 100 / 2 is not one of them.
    got = _open_facets([0], [2], [[True, False, False]], [[4.0, 100.0, 12.0]], [2.0, 2.0, 4.0], 0.0)
    assert got == [(0, 2)]
    # An infinite distance (a zero normal) is reported as 0 by _brute: it raises no bar, and an
    # undecided entry with an infinite distance is kept (its exact sign is cheap to take).
    assert _open_facets([0], [1], [[True, False]], [[4.0, 6.0]], [0.0, 4.0], 0.0) == [(0, 1)]
    assert _open_facets([0], [1], [[True, False]], [[4.0, 1.0]], [2.0, 0.0], 0.0) == [(0, 1)]
    # A point not yet outside keeps every undecided entry, however near, beside one that is outside.
    kept = _open_facets([0, 1, 1], [1, 0, 1], [[True, False], [False, False]], [[5.0, 0.5], [-0.5, 0.0]],
                        norm, 9.0)
    assert kept == [(1, 0), (1, 1)]


# --------------------------------------------------------------------------- many undecided entries, in rounds


def _needle(noise: int, n: int = 60, m: int = 300, seed: int = 5) -> tuple[np.ndarray, np.ndarray]:
    """Integer points along the line t (3, 5, 7) 2**44, every other one off it by up to ``noise`` units,
    and random triangles of them.  With ``noise`` 1 every facet plane nearly passes through every
    point, so nearly every entry is undecided in floats (the wrong hull of near-collinear points
    that made the rounds); with 0 every facet is flat."""
    rng = np.random.default_rng(seed)
    t = np.arange(1, n + 1, dtype=np.int64)[:, None]
    pts = t * np.array([3, 5, 7], dtype=np.int64) * 2**44
    pts[::2] += rng.integers(-noise, noise + 1, size=pts[::2].shape)
    facets = np.array([rng.choice(n, size=3, replace=False) for _ in range(m)])
    return pts.astype(np.float64), facets


def _brute_counting(monkeypatch, pts: np.ndarray, facets: np.ndarray) -> tuple[list[int], float, list[int]]:
    """``_brute`` on every point: the points outside, the distance, and the rows of each exact call."""
    rows: list[int] = []
    exact = cm.orient3d

    def counting(a, b, c, d, **kw):
        rows.append(len(d))
        return exact(a, b, c, d, **kw)

    monkeypatch.setattr(cm, "orient3d", counting)
    outside, worst = cm._brute(pts, [pts[facets[:, k]] for k in range(3)], facets, np.arange(len(pts)))
    monkeypatch.setattr(cm, "orient3d", exact)
    return outside.tolist(), worst, rows


@pytest.mark.parametrize("noise", [1, 0])
def test_many_undecided_entries_are_settled_in_rounds_with_the_same_answer(monkeypatch, noise):
    # Noise 1: most points are outside some facet, nearly all found in the first round, and
    # their other entries are skipped.  Noise 0: every facet is flat, no point is outside,
    # and every entry must be settled (the rounds run until none is left).
    pts, facets = _needle(noise)
    outside, worst, in_rounds = _brute_counting(monkeypatch, pts, facets)
    threshold = cm._ROUNDS_FROM
    monkeypatch.setattr(cm, "_ROUNDS_FROM", 10**12)
    at_once_outside, at_once_worst, at_once = _brute_counting(monkeypatch, pts, facets)
    assert sum(at_once) > threshold  # the undecided entries are many: the rounds ran
    assert outside == at_once_outside == _exact_outside(pts, facets)
    assert worst == at_once_worst
    if noise:
        assert outside and sum(in_rounds) < sum(at_once) / 4
    else:
        assert not outside and sum(in_rounds) == sum(at_once) and len(in_rounds) >= 4


def test_rounds_give_the_answer_of_settling_every_entry(monkeypatch):
    # Every size in rounds: points inside, outside at once, outside only by an entry met in
    # a later round, flat facets; the points and the distance are those of settling all.
    later = mixed = 0
    for seed in range(40):
        pts, facets = _needle(1, n=16, m=(6, 10)[seed % 2], seed=seed)
        monkeypatch.setattr(cm, "_ROUNDS_FROM", 0)
        outside, worst, rows = _brute_counting(monkeypatch, pts, facets)
        monkeypatch.setattr(cm, "_ROUNDS_FROM", 10**12)
        every_outside, every_worst, _ = _brute_counting(monkeypatch, pts, facets)
        assert outside == every_outside == _exact_outside(pts, facets), seed
        assert worst == every_worst, seed
        later += len(rows) >= 3
        mixed += 0 < len(outside) < len(pts)
    assert later >= 10 and mixed >= 10
