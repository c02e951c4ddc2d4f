"""Regressions of the checker's soundness holes (issue 13: F1-F4, Qhull blame, Qhull options).

Each test builds the exact input that showed the hole; its docstring says
what the old checker did with it.
"""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest
from scipy.spatial import ConvexHull

from hullstress.checker import RETRY_OPTIONS, check, qhull_reference
from hullstress.checker import wrap
from hullstress.checker.qhull import options_label
from hullstress.verdict import AGREE, DISAGREE, QHULL_WRONG


# --------------------------------------------------------------------------- inputs


def double_cover(m: int = 5, *, scale: float = 1.0, offset=(2.0, 2.0, 1.0), tiny: float | None = None):
    """A bipyramid whose equator runs twice around (duplicated ring points): a closed surface
    of genus 0, every face on the hull, covering the hull twice.

    Returns (points, triangles counter-clockwise from outside).  ``tiny`` replaces the
    south pole's zero z coordinate (an input that cannot be rescaled exactly).
    """
    ang = 2 * np.pi * np.arange(m) / m
    ring = np.c_[np.cos(ang), np.sin(ang), np.zeros(m)]
    pts = (np.r_[[[0.0, 0.0, 1.0], [0.0, 0.0, -1.0]], ring, ring] + offset) * scale
    if tiny is not None:
        pts[1, 2] = tiny
    equator = list(range(2, 2 + 2 * m))
    faces = []
    for j in range(2 * m):
        a, b = equator[j], equator[(j + 1) % (2 * m)]
        faces += [(0, a, b), (1, b, a)]
    return pts, np.array(faces)


def oriented_hull(points: np.ndarray) -> np.ndarray:
    """scipy's hull, each triangle turned counter-clockwise seen from outside."""
    hull = ConvexHull(points)
    tri = hull.simplices.copy()
    a, b, c = (points[tri[:, k]] for k in range(3))
    inward = np.einsum("ij,ij->i", np.cross(b - a, c - a), hull.equations[:, :3]) < 0
    tri[inward] = tri[inward][:, ::-1]
    return tri


def needle_tetrahedron(seed: int, t: float = 1e-12) -> np.ndarray:
    """Four vertices within t of a unit segment, randomly rotated and offset (rounded)."""
    rng = np.random.default_rng(seed)
    v = np.array([[0.0, 0, 0], [1.0, 0, 0], [0.5, t, 0], [0.5, 0, t]])
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    return v @ q.T + rng.uniform(-1, 1, 3)


# --------------------------------------------------------------------------- F1


def test_f1_double_cover_at_scale_1e20_with_a_1e300_coordinate_fails():
    """F1: the ray of the wrap test was the interior point plus a unit normal vector;
    at 1e20 (unscalable because of the 1e-300 coordinate) that rounds back onto the
    point, every ray grazed, the test was skipped, and the double cover passed."""
    pts, faces = double_cover(scale=1e20, tiny=1e-300)
    v = check(pts, faces)
    assert v.containment and v.manifoldness  # every face lies on the hull, the surface is a sphere
    assert not v.convexity and not v.ok
    assert "wraps 2 times" in v.detail
    assert v.severity == "gross"


@pytest.mark.parametrize("scale,tiny", [(1.0, None), (1e20, 1e-300), (2.0**-1000, None), (1e300, 1e-300)])
def test_double_cover_fails_at_every_scale(scale, tiny):
    pts, faces = double_cover(scale=scale, tiny=tiny)
    v = check(pts, faces, qhull=False)
    assert not v.convexity and "wraps 2 times" in v.detail


def test_wrap_count_is_decided_when_the_ray_meets_every_edge(monkeypatch):
    """With the ray point forced onto the interior point itself, every edge plane
    contains it: the count rests entirely on the symbolic perturbation."""
    monkeypatch.setattr(wrap, "ray_point", lambda origin, extent, seed: np.array(origin, dtype=np.float64))
    pts, faces = double_cover()
    assert "wraps 2 times" in check(pts, faces, qhull=False).detail
    ball = np.random.default_rng(1).normal(size=(60, 3))
    assert check(ball, oriented_hull(ball), qhull=False).ok
    angles = 2 * np.pi * np.arange(7) / 7
    heptagon = np.c_[np.cos(angles), np.sin(angles)] * 1e20
    assert check(heptagon, np.arange(7), qhull=False).ok
    assert "winds 2 times" in check(heptagon, (2 * np.arange(7)) % 7, qhull=False).detail


# --------------------------------------------------------------------------- F2


@pytest.mark.parametrize("seed", range(6))
def test_f2_thin_tetrahedron_agrees_with_qhull_whatever_the_face_order(seed):
    """F2: the volumes were float sums whose reference point was the first face's first
    vertex; on a needle tetrahedron the rounding of each term exceeded the tolerance,
    so Qhull's own faces, reordered, were a gross qhull_agreement failure."""
    pts = needle_tetrahedron(seed)
    ref = qhull_reference(pts)
    assert ref.qhull_ok
    tri = ref.faces.triangles()
    volumes = set()
    for perm in ([0, 1, 2, 3], [1, 2, 3, 0], [3, 2, 1, 0], [2, 0, 3, 1]):
        for rot in ([0, 1, 2], [1, 2, 0], [2, 0, 1]):
            v = check(pts, tri[perm][:, rot], reference=ref, reuse_reference=False)
            assert v.ok and v.qhull_agreement == AGREE and v.severity == "none", v.detail
            volumes.add(v.volume)
    assert len(volumes) == 1  # bit-identical, not just close


def test_recorded_volume_does_not_depend_on_face_order_or_rotation():
    rng = np.random.default_rng(5)
    pts = rng.normal(size=(300, 3)) * [1.0, 1e-7, 1e3] + 1e4
    tri = oriented_hull(pts)
    base = check(pts, tri, qhull=False).volume
    for _ in range(5):
        shuffled = tri[rng.permutation(len(tri))]
        turn = rng.integers(0, 3, len(tri))
        shuffled = np.take_along_axis(shuffled, (turn[:, None] + np.arange(3)) % 3, axis=1)
        assert check(pts, shuffled, qhull=False).volume == base
    # Polygon faces: the same, whichever vertex each polygon is listed from.
    cube = np.array([[x, y, z] for x in (0.0, 1.0) for y in (0.0, 1.0) for z in (0.0, 1.0)]) * 0.1
    quads = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]]
    first = check(cube, quads, qhull=False)
    rolled = check(cube, [q[1:] + q[:1] for q in reversed(quads)], qhull=False)
    assert first.ok and rolled.ok and first.volume == rolled.volume


# --------------------------------------------------------------------------- F3


def test_f3_mixed_magnitudes_do_not_overflow_the_area_sum():
    """F3: a square at 1e300 beside a point at 1e-300 cannot be rescaled exactly; the
    area's math.fsum raised 'intermediate overflow in fsum' and the row became an
    internal error."""
    square = np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]) * 1e300
    pts = np.r_[square, [[1e-300, 0.0]]]
    for qhull in (False, True):
        v = check(pts, [0, 1, 2, 3], qhull=qhull)
        assert v.ok and v.volume == np.inf  # 4e600: beyond the doubles, recorded as inf
    assert not check(pts, [0, 1, 4, 2, 3], qhull=False).ok  # a wrong hull still fails (point 4 is inside)


def test_f3_mixed_magnitudes_in_3d():
    cube = np.array([[x, y, z] for x in (-1.0, 1.0) for y in (-1.0, 1.0) for z in (-1.0, 1.0)])
    pts = np.r_[cube * 1e300, [[1e-300, 0.0, 0.0]]]
    v = check(pts, oriented_hull(cube))
    assert v.ok and v.volume == np.inf and v.n_extreme == 8
    assert v.qhull_agreement in (AGREE, QHULL_WRONG)


# --------------------------------------------------------------------------- F4


def _pyramid(k: int, *, star: bool = False, dent: bool = False):
    ang = 2 * np.pi * np.arange(k) / k
    base = np.c_[np.cos(ang), np.sin(ang), np.zeros(k)]
    if dent:
        base[k // 2, :2] *= 0.2  # inside the chord of its neighbours: a reflex vertex
    pts = np.r_[base, [[0.0, 0.0, 1.0]]]
    order = (3 * np.arange(k)) % k if star else np.arange(k)
    faces = [order[::-1].tolist()] + [[int(order[i]), int(order[(i + 1) % k]), k] for i in range(k)]
    return pts, faces


def test_f4_a_2000_gon_face_costs_bounded_memory():
    """F4: the polygon convexity test held every (edge, vertex) pair of a face: 2000
    vertices took 1.9 GB.  Now the test is O(k) and the containment cones are chunked."""
    pts, faces = _pyramid(2000)
    pts = np.r_[pts, np.random.default_rng(0).random((300, 3)) * [0.5, 0.5, 0.3]]  # points inside
    tracemalloc.start()
    try:
        v = check(pts, faces, qhull=False)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert v.ok, v.detail
    assert peak < 64 * 2**20, f"peak {peak / 2**20:.0f} MiB"


@pytest.mark.parametrize("k", [5, 7, 2000])
def test_non_convex_and_doubly_wound_polygon_faces_are_still_caught(k):
    pts, faces = _pyramid(k, dent=True)
    v = check(pts, faces, qhull=False)
    assert not v.convexity and v.n_degenerate_faces == 1
    if k % 3:  # a {k/3} star base winds three times
        pts, faces = _pyramid(k, star=True)
        v = check(pts, faces, qhull=False)
        assert not v.convexity and v.offending["degenerate_faces"] == (0,)
        assert v.severity == "gross"


# --------------------------------------------------------------------------- Qhull is a witness


def test_qhull_wrong_is_not_charged_to_the_algorithm():
    """Qhull drops a point 1e-17 outside the unit square's bottom edge (within its
    roundoff), so its own hull fails the exact checks.  The exact pentagon used to get
    qhull_agreement None, and Qhull's own wrong square qhull_agreement True."""
    pts = np.array([[0.0, 0], [1, 0], [1, 1], [0, 1], [0.5, -1e-17]])
    ref = qhull_reference(pts)
    assert ref.qhull_ok is False
    exact = check(pts, [0, 4, 1, 2, 3], reference=ref)
    assert exact.ok and exact.qhull_agreement == QHULL_WRONG and exact.failed_checks == ()
    assert "Qhull's own hull fails the exact checks" in exact.detail
    square = check(pts, [0, 1, 2, 3], reference=ref)
    assert square.failed_checks == ("containment",) and square.qhull_agreement == QHULL_WRONG
    row = exact.as_row()
    assert row["qhull_agreement"] == "qhull-wrong" and row["failed_checks"] == "" and row["qhull_ok"] is False


def test_disagreement_with_a_certified_qhull_is_a_failed_check():
    pts = np.array([[0.0, 0], [1, 0], [1, 1], [0, 1], [0.5, 0.5]])
    v = check(pts, [0, 1, 4, 3])
    assert v.qhull_agreement == DISAGREE and "qhull_agreement" in v.failed_checks


# --------------------------------------------------------------------------- Qhull options


@pytest.mark.parametrize("options", RETRY_OPTIONS)
def test_every_retry_option_set_is_a_valid_qhull_option_set(options):
    """'Qbb Qc Qz Q12' ended in QH6047 (Qz is for Delaunay) on every input."""
    pts = np.random.default_rng(0).random((30, 3))
    ConvexHull(pts, qhull_options=options)  # raises QhullError on an option error
    ConvexHull(pts[:, :2], qhull_options=options)


def test_the_options_that_produced_the_reference_are_recorded():
    # A disc offset by 1e15: Qhull's default run finds its initial simplex flat.
    rng = np.random.default_rng(1)
    disc = rng.normal(size=(24, 2))
    disc = disc / np.linalg.norm(disc, axis=1)[:, None] * rng.random((24, 1)) ** 0.5 + 1e15
    ref = qhull_reference(disc)
    tried = ("",) + RETRY_OPTIONS
    assert ref.attempts and ref.attempts[0].startswith("Qt: ")
    assert [a.split(":")[0] for a in ref.attempts] == [options_label(o) for o in tried[: len(ref.attempts)]]
    assert ref.options == options_label(tried[len(ref.attempts)])  # the first set that did not fail
    assert check(disc, ref.faces, reference=ref).qhull_options == ref.options
    # Exactly coplanar: only the joggle succeeds.
    flat = np.c_[np.random.default_rng(2).random((20, 2)), np.zeros(20)]
    ref = qhull_reference(flat)
    assert ref.options == "QJ" and ref.qhull_ok is False
    assert [a.split(":")[0] for a in ref.attempts] == [options_label(o) for o in tried[: tried.index("QJ")]]


def test_an_unscalable_input_runs_qhull_on_a_rounded_copy_and_says_so():
    cube = np.array([[x, y, z] for x in (-1.0, 1.0) for y in (-1.0, 1.0) for z in (-1.0, 1.0)])
    ref = qhull_reference(np.r_[cube * 1e300, [[1e-300, 0.0, 0.0]]])
    assert ref.options.endswith(", rounded)") and ref.qhull_ok
