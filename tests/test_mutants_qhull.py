"""Qhull as a witness (``hullstress/checker/qhull.py``), pinned where the mutation run found it loose.

Each test here was written against mutants of ``hullstress/checker/qhull.py``
that survived the rest of the fast suite (``tools/mutation.sh``, docs/testing.md "Mutation
testing").  Every expectation comes from the documented behaviour (the module
and field docstrings, docs/design.md's "qhull agreement") or from the geometry
worked out by hand (extreme sets, volumes and areas of boxes and tetrahedra,
Fractions), never from the checker's own output.
"""

from __future__ import annotations

import math
from fractions import Fraction
from types import SimpleNamespace

import numpy as np
import pytest
from scipy.spatial import QhullError

from hullstress.checker import qhull as qhull_module
from hullstress.checker._geometry import Interior, distround
from hullstress.checker.qhull import (
    DEFAULT_OPTIONS,
    REPAIR_OPTIONS,
    RETRY_OPTIONS,
    _first_line,
    _oriented_faces,
    _unscale,
    certified_extremes,
    face_set_key,
    options_label,
    qhull_reference,
    volume_tolerance,
)
from hullstress.checker.severity import VOLUME_TOLERANCE_MULTIPLE
from hullstress.contract import FaceSet

# --------------------------------------------------------------------------- inputs and exact helpers

_TETRA = np.array([[0.0, 0, 0], [4, 0, 0], [0, 4, 0], [0, 0, 4], [1, 1, 1]])  # point 4 strictly inside
_CUBE = np.array([[x, y, z] for x in (0.0, 2.0) for y in (0.0, 2.0) for z in (0.0, 2.0)])  # vertex 4x + 2y + z
_CUBE_QUADS = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]]
_CUBE_TRIANGLES = [[f[0], f[k], f[k + 1]] for f in _CUBE_QUADS for k in (1, 2)]
_LABELS = [options_label(o) for o in ("",) + RETRY_OPTIONS]


def _fr(row) -> list[Fraction]:
    return [Fraction(x) for x in row]


def _outward(points: np.ndarray, tri, inside) -> bool:
    """Whether triangle ``tri`` turns counter-clockwise seen from outside: ``inside`` strictly below it (Fractions)."""
    a, b, c = (_fr(points[i]) for i in tri)
    o = _fr(inside)
    u, v, w = ([p[k] - a[k] for k in range(3)] for p in (b, c, o))
    det = u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) + u[2] * (v[0] * w[1] - v[1] * w[0])
    return det < 0


def _smallest_rotation(t):
    return min(tuple(t[k:]) + tuple(t[:k]) for k in range(len(t)))


# --------------------------------------------------------------------------- small helpers


def test_options_label_is_what_scipy_runs():
    assert DEFAULT_OPTIONS == "Qt"
    assert [options_label(o) for o in ("", "Q12", "QbB", "QbB Q12", "QJ", "QbB QJ", "Qx")] == [
        "Qt", "Qt Q12", "Qt QbB", "Qt QbB Q12", "QJ", "QbB QJ", "Qt Qx",
    ]
    assert options_label("  ") == "Qt"


def test_first_line_of_an_error():
    assert _first_line(QhullError("\n\nQH6154 Qhull precision error: flat\nmore text\n")) == "QhullError: QH6154 Qhull precision error: flat"
    assert _first_line(ValueError("  padded  \n")) == "ValueError: padded"
    assert _first_line(RuntimeError("")) == "RuntimeError"  # no message: the type alone
    assert _first_line(RuntimeError(" \n \n")) == "RuntimeError"


def test_unscale_saturates_with_the_sign():
    assert _unscale(3.0, 4) == 48.0 and _unscale(3.0, -1) == 1.5
    assert _unscale(1.0, 5000) == math.inf and _unscale(-1.0, 5000) == -math.inf
    assert _unscale(1.0, -5000) == 0.0


# --------------------------------------------------------------------------- invalid input


@pytest.mark.parametrize(
    ("points", "error", "n", "dim"),
    [
        ([["a", "b"]], "points must be a numeric array of shape (n, 2) or (n, 3): ", 0, 0),
        (np.zeros((3, 4)), "points must have shape (n, 2) or (n, 3), got (3, 4)", 0, 0),
        (np.zeros(3), "points must have shape (n, 2) or (n, 3), got (3,)", 0, 0),
        (np.array([[0.0, 1.0], [np.inf, 0.0]]), "points must be finite, got NaN or inf coordinates", 2, 2),
        (np.array([[0.0, 1.0, np.nan]]), "points must be finite, got NaN or inf coordinates", 1, 3),
        (np.zeros((0, 3)), "points is empty", 0, 3),
    ],
)
def test_invalid_input_is_recorded_not_raised(points, error, n, dim):
    ref = qhull_reference(points)
    assert ref.error.startswith(error)
    assert (ref.n_points, ref.dim) == (n, dim)
    assert ref.vertices is None and ref.faces is None and ref.volume is None and ref.options is None
    assert ref.qhull_ok is None and ref.extreme is None and ref.affine_rank is None and ref.simplex is None
    assert ref.attempts == () and ref.qhull_detail == "" and ref.distround == 0.0
    assert ref.face_key is None and not ref.same_faces(np.array([0, 1, 2]))


# --------------------------------------------------------------------------- a certified reference


def test_reference_of_a_tetrahedron_with_an_inner_point():
    ref = qhull_reference(_TETRA)
    assert ref.error is None and ref.qhull_ok is True and ref.options == "Qt" and ref.attempts == ()
    assert sorted(ref.vertices.tolist()) == [0, 1, 2, 3]
    assert ref.extreme.tolist() == [0, 1, 2, 3] and ref.extreme is ref.extreme  # kept after first use
    assert ref.volume == 64 / 6 and ref.affine_rank == 3 and ref.n_points == 5 and ref.dim == 3
    assert ref.exponent == 0 and ref.points is not None and np.array_equal(ref.scaled, _TETRA)
    assert sorted(ref.simplex.tolist()) == [0, 1, 2, 3]
    assert ref.qhull_detail == "" and ref.certificate.certified
    tri = ref.faces.to_python()
    assert len(tri) == 4 and all(_outward(_TETRA, t, _TETRA[4]) for t in tri)
    assert all(t[0] == min(t) for t in tri)  # stored from the lowest index
    assert ref.face_key.tolist() == sorted((a * 5 + b) * 5 + c for a, b, c in (_smallest_rotation(t) for t in tri))
    assert ref.distround == distround(_TETRA) > 0
    assert ref.as_dict() == {
        "qhull_options": "Qt", "qhull_ok": True, "qhull_volume": 64 / 6, "qhull_error": None,
        "distround": distround(_TETRA), "affine_rank": 3,
    }


def test_reference_of_a_polygon_is_its_counter_clockwise_cycle():
    # Corners listed out of order: counter-clockwise they are 0, 3, 1, 2 (4 inside, 5 on an edge).
    pts = np.array([[0.0, 0], [4, 4], [0, 4], [4, 0], [1, 2], [2, 0]])
    ref = qhull_reference(pts)
    assert ref.qhull_ok is True and ref.volume == 16.0 and ref.affine_rank == 2
    cycle = ref.faces.tolist()
    assert sorted(cycle) == [0, 1, 2, 3] and np.array_equal(ref.vertices, ref.faces) and ref.vertices is not ref.faces
    assert ref.vertices.dtype == np.int64 and ref.faces.dtype == np.int64
    k = cycle.index(0)
    assert cycle[k:] + cycle[:k] == [0, 3, 1, 2]  # counter-clockwise
    assert ref.face_key.tolist() == [0, 3, 1, 2] and ref.extreme.tolist() == [0, 1, 2, 3]


def test_same_faces_in_any_order_and_rotation_never_reversed():
    ref = qhull_reference(_TETRA)
    tri = ref.faces.to_python()
    shuffled = [t[1:] + t[:1] for t in tri[::-1]]
    assert ref.same_faces(FaceSet.from_triangles(shuffled))
    assert not ref.same_faces(FaceSet.from_triangles([t[::-1] for t in tri]))
    assert not ref.same_faces(FaceSet.from_triangles(tri[:3]))
    assert not ref.same_faces(FaceSet.from_triangles(tri[:3] + [[4, 1, 2]]))
    assert not ref.same_faces(FaceSet.from_polygons([[0, 1, 2, 3]] + tri[1:]))  # a quadrilateral: never compared
    square = qhull_reference(np.array([[0.0, 0], [4, 0], [4, 4], [0, 4]]))
    assert square.same_faces(np.array([2, 3, 0, 1])) and not square.same_faces(np.array([3, 2, 1, 0]))
    assert not square.same_faces(np.array([0, 1, 2]))


def test_a_duplicated_corner_is_one_extreme_point():
    pts = np.r_[_TETRA, _TETRA[[0, 2]]]  # points 5 and 6 repeat corners 0 and 2
    ref = qhull_reference(pts)
    assert ref.qhull_ok is True
    got = ref.extreme.tolist()
    assert len(got) == 4 and sorted(map(tuple, pts[got].tolist())) == sorted(map(tuple, _TETRA[:4].tolist()))


# --------------------------------------------------------------------------- face_set_key


@pytest.mark.parametrize("n", [9, 100, 2**21 - 1, 2**21, 2**22 + 5])
def test_face_set_key_is_canonical(n):
    base = n - 9  # indices near n: both the one-integer keys and the rows above 2**21
    tri = (np.array(_CUBE_TRIANGLES) + base).tolist()
    key = face_set_key(FaceSet.from_triangles(tri), n)
    shuffled = [t[2:] + t[:2] for t in tri[::-1]]
    assert np.array_equal(face_set_key(FaceSet.from_triangles(shuffled), n), key)
    assert not np.array_equal(face_set_key(FaceSet.from_triangles([t[::-1] for t in tri]), n), key)
    other = tri[:-1] + [[tri[-1][0], tri[-1][1], base + 8]]
    assert not np.array_equal(face_set_key(FaceSet.from_triangles(other), n), key)
    assert len(key) == 12
    if n < 2**21:
        assert key.tolist() == sorted((a * n + b) * n + c for a, b, c in map(_smallest_rotation, tri))
    else:
        assert key.tolist() == sorted(map(list, map(_smallest_rotation, tri)))
    assert face_set_key(FaceSet.from_polygons(_CUBE_QUADS), 8) is None


def test_face_set_key_of_a_polygon():
    assert face_set_key(np.array([5, 7, 2, 9]), 10).tolist() == [2, 9, 5, 7]
    assert face_set_key([3, 1, 2], 4).tolist() == [1, 2, 3]
    assert face_set_key(np.zeros(0, np.int64), 4).tolist() == []


# --------------------------------------------------------------------------- volume_tolerance


def test_volume_tolerance_is_the_multiple_of_distround_times_the_area():
    dr = distround(_CUBE)
    assert volume_tolerance(_CUBE, FaceSet.from_polygons(_CUBE_QUADS), dr) == Fraction(VOLUME_TOLERANCE_MULTIPLE) * Fraction(dr) * 24
    assert volume_tolerance(_CUBE, FaceSet.from_polygons(_CUBE_QUADS), dr, area=3.0) == Fraction(VOLUME_TOLERANCE_MULTIPLE) * Fraction(dr) * 3
    square = _CUBE[[0, 4, 6, 2], :2]
    assert volume_tolerance(square, np.arange(4), 0.5) == Fraction(VOLUME_TOLERANCE_MULTIPLE) * Fraction(1, 2) * 8


@pytest.mark.parametrize("dim", [2, 3])
def test_volume_tolerance_scales_with_the_dth_power_even_where_the_area_overflows(dim):
    # DISTround is linear and the area homogeneous of degree d - 1 under a power-of-two
    # scaling, so the tolerance is multiplied by 2**(d k); at 2**1000 the float area
    # overflows (the fallback on a copy brought to magnitude 1 gives the same value).
    pts, faces = (_CUBE[[0, 4, 6, 2], :2], np.arange(4)) if dim == 2 else (_CUBE, FaceSet.from_polygons(_CUBE_QUADS))
    pts = pts - 1.0  # the box [-1, 1]^d
    base = volume_tolerance(pts, faces, distround(pts))
    assert base > 0
    for k in (7, -9, 600, 1000, 1022):
        scaled = np.ldexp(pts, k)
        got = volume_tolerance(scaled, faces, distround(scaled))
        assert got == base * Fraction(2) ** (dim * k), k
    # A point far below the others (the input cannot be rescaled exactly) changes nothing.
    tiny = np.r_[np.ldexp(pts, 1000), np.full((1, dim), 2.0**-1000)]
    assert volume_tolerance(tiny, faces, distround(tiny)) == base * Fraction(2) ** (dim * 1000)


# --------------------------------------------------------------------------- Qhull's options and scale


def test_every_failed_option_set_is_recorded_and_the_first_success_named():
    flat = np.c_[np.array([[0.0, 0], [1, 0], [0, 1], [1, 1], [0.3, 0.6]]), np.zeros(5)]  # exactly coplanar
    ref = qhull_reference(flat)
    assert ref.options == "QJ" and ref.qhull_ok is False and ref.affine_rank == 2
    assert [a.split(": ")[0] for a in ref.attempts] == ["Qt", "Qt Q12", "Qt QbB", "Qt QbB Q12"]
    assert all(": QhullError: QH" in a for a in ref.attempts)
    # Options asked for come first, then the usual fallbacks.
    ref = qhull_reference(flat, options="Q12")
    assert [a.split(": ")[0] for a in ref.attempts] == ["Qt Q12", "Qt Q12", "Qt QbB", "Qt QbB Q12"] and ref.options == "QJ"
    ref = qhull_reference(_TETRA, options="QbB")
    assert ref.options == "Qt QbB" and ref.attempts == () and ref.qhull_ok is True


@pytest.mark.parametrize(
    ("points", "rank", "extreme"),
    [
        (np.array([[0.0, 0, 0], [1, 1, 1], [2, 0, 0]]), 2, None),  # too few points in 3D: no extreme set
        (np.zeros((1, 3)), 0, None),
        (np.array([[1.0, 1.0], [0.0, 0.0]]), 1, [0, 1]),  # 2D: the exact monotone chain, sorted
        (np.array([[2.0, 2.0]]), 0, [0]),
        (np.array([[0.0, 0, 0], [1, 1, 1], [2, 0, 0]]) * 2.0**200, 2, None),  # rescaled by 2**-202
    ],
)
def test_when_every_option_set_fails(points, rank, extreme):
    ref = qhull_reference(points)
    assert ref.vertices is None and ref.faces is None and ref.volume is None and ref.options is None
    assert ref.qhull_ok is None and ref.face_key is None and ref.qhull_detail == ""
    assert [a.split(": ")[0] for a in ref.attempts] == _LABELS
    assert ref.error == "Qhull failed with every option set: " + ref.attempts[-1]
    assert ref.error.startswith("Qhull failed with every option set: QbB QJ: QhullError: ")
    assert ref.affine_rank == rank and len(ref.simplex) == rank + 1
    assert (None if ref.extreme is None else ref.extreme.tolist()) == extreme
    assert ref.distround == distround(points) and ref.n_points == len(points) and ref.dim == points.shape[1]
    top = np.abs(points).max()
    k = 0 if top == 0 or 2.0**-100 <= top <= 2.0**100 else -math.frexp(top)[1]  # exact_scale's documented range
    assert np.array_equal(ref.points, points) and ref.exponent == k and np.array_equal(ref.scaled, np.ldexp(points, k))


@pytest.mark.parametrize(
    ("k", "note"),
    [(399, ""), (400, " (on input scaled by 2^-402)"), (-401, ""), (-402, " (on input scaled by 2^400)"), (-700, " (on input scaled by 2^698)")],
)
def test_qhull_runs_on_a_rescaled_copy_outside_its_safe_range(k, note):
    # Qhull's safe range is [2**-400, 2**400] for the largest magnitude, here 2**(k + 1);
    # outside it, the exact scaling by 2**-(k + 2) brings that magnitude to 1/2.
    pts = np.ldexp(_CUBE, k)
    ref = qhull_reference(pts)
    label, _, rest = ref.options.partition(" (")
    assert label in _LABELS and (" (" + rest if rest else "") == note  # at 2**400 Qhull's default run fails: "Qt QbB"
    assert ref.qhull_ok is True
    assert ref.extreme.tolist() == list(range(8))
    assert ref.volume == _unscale(8.0, 3 * k)  # 8 * 2**(3k), inf beyond the doubles
    assert np.array_equal(ref.points, pts) and np.array_equal(np.ldexp(ref.scaled, -ref.exponent), pts)


def test_an_input_that_cannot_be_scaled_exactly_runs_on_a_rounded_copy():
    pts = np.r_[(_CUBE - 1.0) * 1e300, [[1e-300, 0.0, 0.0]]]
    ref = qhull_reference(pts)
    k = -math.frexp(1e300)[1]
    assert ref.exponent == 0 and ref.options == f"Qt (on input scaled by 2^{k}, rounded)"
    assert ref.qhull_ok is True and ref.extreme.tolist() == list(range(8)) and ref.volume == math.inf


# --------------------------------------------------------------------------- Qhull's hull is wrong


def test_a_wrong_qhull_hull_is_recorded_and_the_extreme_set_repaired():
    # A point one unit in the last place above the centre of a cube's top face: Qhull takes it
    # as coplanar and drops it, so its hull fails containment; the exact extreme set has it.
    pts = np.r_[_CUBE / 2, [[0.5, 0.5, 1 + 2.0**-52]]]
    ref = qhull_reference(pts)
    assert ref.options == "Qt" and ref.qhull_ok is False
    assert ref.qhull_detail == "containment: 1 points outside"
    assert sorted(ref.vertices.tolist()) == list(range(8)) and ref.volume == 1.0
    assert ref.extreme.tolist() == list(range(9))
    assert ref.affine_rank == 3
    # The same input at 2**500: Qhull runs on the exactly rescaled copy; its default run there
    # repeats the failure, the joggled one repairs the extreme set.
    big = qhull_reference(pts * 2.0**500)
    assert big.options == "Qt (on input scaled by 2^-501)" and big.qhull_ok is False
    assert big.extreme.tolist() == list(range(9)) and big.volume == math.inf


def test_a_wrong_qhull_polygon():
    pts = np.array([[0.0, 0], [1, 0], [1, 1], [0, 1], [0.5, -1e-17]])
    ref = qhull_reference(pts)
    assert ref.qhull_ok is False and "containment: 1 points outside" in ref.qhull_detail
    assert ref.extreme.tolist() == [0, 1, 2, 3, 4]  # 4 is strictly below the bottom edge
    assert sorted(ref.vertices.tolist()) == [0, 1, 2, 3]


# --------------------------------------------------------------------------- certified_extremes


def test_certified_extremes_of_a_tetrahedron_and_of_a_superset():
    interior = Interior.from_simplex(_TETRA[:4])
    assert REPAIR_OPTIONS == ("", "QJ")
    assert certified_extremes(_TETRA, np.arange(4), interior).tolist() == [0, 1, 2, 3]
    assert certified_extremes(_TETRA, [4, 3, 2, 1, 0, 3], interior).tolist() == [0, 1, 2, 3]
    assert certified_extremes(_TETRA, np.arange(4), interior, options=("QJ",)).tolist() == [0, 1, 2, 3]
    assert certified_extremes(_TETRA, np.arange(1, 5), interior) is None  # corner 0 missing: nothing certifies
    assert certified_extremes(_TETRA, np.arange(3), interior) is None
    assert certified_extremes(_TETRA, np.arange(4), interior, options=("Qz",)) is None  # an option error


def test_certified_extremes_past_a_failing_option_set():
    # A tetrahedron 1e-16 thick: Qhull's default run finds its initial simplex flat, the
    # joggled run gives the four faces, which certify against the exact points.
    pts = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0.25, 0.25, 1e-16]])
    interior = Interior.from_simplex(pts)
    with pytest.raises(QhullError):
        from scipy.spatial import ConvexHull

        ConvexHull(pts)
    assert certified_extremes(pts, np.arange(4), interior).tolist() == [0, 1, 2, 3]
    assert certified_extremes(pts, np.arange(4), interior, options=("",)) is None


# --------------------------------------------------------------------------- _oriented_faces


def _fake_hull(simplices, equations) -> SimpleNamespace:
    """What _oriented_faces reads of a scipy ConvexHull: the triangles and Qhull's facet planes."""
    return SimpleNamespace(simplices=np.array(simplices), equations=np.c_[np.array(equations, dtype=np.float64), np.zeros(len(equations))])


_TETRA_OUTWARD = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]  # counter-clockwise seen from outside
_TETRA_MIXED = [[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]]  # the first and the third clockwise


def test_oriented_faces_follow_qhull_normals_where_they_are_clear():
    pts = _TETRA[:4]
    assert [_outward(pts, t, _TETRA[4]) for t in _TETRA_OUTWARD + _TETRA_MIXED] == [True] * 4 + [False, True, False, True]
    outward = [[0, 0, -1], [0, -1, 0], [-1, 0, 0], [3**-0.5] * 3]
    asked = []
    got = _oriented_faces(pts, _fake_hull(_TETRA_MIXED, outward), lambda: asked.append(1))
    assert got.tolist() == _TETRA_OUTWARD and got.dtype == np.int64
    assert not asked  # the interior point is asked for only where the normals leave it open


def test_oriented_faces_ask_the_exact_interior_point_where_qhull_normals_are_unsure():
    # Normals perpendicular to the faces (or nearly: 1e-9 of the face normal) say nothing;
    # the exact side of the interior point orients those faces.
    pts = _TETRA[:4]
    sideways = [[1, 0, 1e-9], [1, 0, 1e-9], [0, 1, 0], [1, -1, 0]]
    interior = Interior.from_simplex(pts)
    asked = []

    def lazy():
        asked.append(1)
        return interior

    got = _oriented_faces(pts, _fake_hull(_TETRA_MIXED, sideways), lazy)
    assert got.tolist() == _TETRA_OUTWARD and len(asked) == 1
    assert _oriented_faces(pts, _fake_hull(_TETRA_MIXED, sideways), interior).tolist() == _TETRA_OUTWARD
    # Without an interior point the unsure faces keep the float test's (here: no) flip.
    assert _oriented_faces(pts, _fake_hull(_TETRA_MIXED, sideways), None).tolist() == _TETRA_MIXED
    # A clear normal wins over the interior point; only the unsure faces are asked about.
    clear_wrong = [[0, 0, 1], [1, 0, 1e-9], [0, 1, 0], [1, -1, 0]]  # face 0 "faces up" by Qhull's word
    got = _oriented_faces(pts, _fake_hull(_TETRA_MIXED, clear_wrong), interior)
    assert got.tolist() == [[0, 1, 2], [0, 1, 3], [0, 3, 2], [1, 2, 3]]


def _normals_turned_sideways(monkeypatch):
    """Make every Qhull facet normal perpendicular to its facet (Qhull's triangles kept): the
    float orientation test can then decide nothing, the exact interior point must."""
    real = qhull_module.ConvexHull

    def sideways(points, qhull_options=None):
        hull = real(points, qhull_options=qhull_options)
        n = hull.equations[:, :3]
        perp = np.cross(n, [0.6, 0.8, 0.0])
        return SimpleNamespace(simplices=hull.simplices, equations=np.c_[perp, hull.equations[:, 3]])

    monkeypatch.setattr(qhull_module, "ConvexHull", sideways)


def test_the_exact_interior_point_orients_what_qhull_normals_leave_open(monkeypatch):
    _normals_turned_sideways(monkeypatch)
    interior = Interior.from_simplex(_TETRA[:4])
    assert certified_extremes(_TETRA, np.arange(5), interior).tolist() == [0, 1, 2, 3]
    ref = qhull_reference(_TETRA)
    assert ref.qhull_ok is True and ref.extreme.tolist() == [0, 1, 2, 3]
    assert all(_outward(_TETRA, t, _TETRA[4]) for t in ref.faces.to_python())
    # The repair after a wrong Qhull hull (see above) orients its faces the same way.
    pts = np.r_[_CUBE / 2, [[0.5, 0.5, 1 + 2.0**-52]]]
    ref = qhull_reference(pts)
    assert ref.qhull_ok is False and ref.extreme.tolist() == list(range(9))
