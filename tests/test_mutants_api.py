"""``hullstress/checker/api.py`` (the ``check`` entry point) pinned where the mutation run found it loose.

Each test here was written against mutants of ``api.py`` that survived the
rest of the fast suite (``tools/mutation.sh``, docs/testing.md "Mutation testing").
Every expectation comes from the documented behaviour (``check``'s
docstring, docs/design.md's verdict semantics, the severity and DISTround
formulas as documented) or is worked out by hand in integers or Fractions,
never from the checker's own output.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from hullstress.checker import check, qhull_reference

_EPS = 2.0**-52


def _distround(maxabs: float, sumcoord: float, d: int) -> float:
    """Qhull's DISTround as documented (``hullstress.checker.distround``, Qhull's qh_detroundoff)."""
    return _EPS * (d * min(math.sqrt(d) * maxabs, sumcoord) * 1.01 + maxabs)


# The square [0, 2]^2: MAXabs 2, MAXsumcoord 2 + 2.
_SQUARE = [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]]
_DR_SQUARE = _distround(2.0, 4.0, 2)


def test_a_cut_corner_in_2d_by_hand():
    # The square 0..3 with its centre 4: the hull 0 1 4 3 cuts the corner 2 = (2, 2) off
    # (orient2d((2, 0), (1, 1), (2, 2)) = -2: right of the edge 1 -> 4, outside).
    pts = np.array(_SQUARE + [[1.0, 1.0]])
    v = check(pts, [0, 1, 4, 3])
    assert not v.ok
    assert v.offending["containment"] == (2,)
    assert v.offending["missing_extreme"] == (2,)
    assert v.n_extreme == 4 and v.n_outside == 1 and v.n_hull_vertices == 4


def test_a_square_walked_twice_disagrees_with_qhull_by_its_whole_area():
    # Shoelace: the walk 0 1 2 3 0 1 2 3 encloses 2 x 4 = 8; Qhull's square 4.  The gap,
    # 4, is 1 relative to Qhull's area, and as a mean thickness over Qhull's perimeter 8
    # it is 4 / (8 DISTround) DISTround (qhull_volume in the severity; api._agreement:
    # gap * VOLUME_TOLERANCE_MULTIPLE / tol, tol = VOLUME_TOLERANCE_MULTIPLE * DISTround * area).
    v = check(np.array(_SQUARE), [0, 1, 2, 3, 0, 1, 2, 3])
    assert v.qhull_agreement == "disagree" and v.qhull_ok is True
    assert v.volume == 8.0 and v.qhull_volume == 4.0
    assert v.detail.endswith("; qhull: volume differs by 1 (relative)")
    assert "extreme vertices against" not in v.detail  # the same four corners
    assert v.severity == "gross"  # a manifoldness failure is gross anyway
    # No point is outside and no edge is reflex: the worst violation is the volume gap.
    assert v.max_violation == pytest.approx(4.0 / (8.0 * _DR_SQUARE), rel=1e-9)


def test_a_corner_missed_within_qhulls_volume_tolerance_disagrees_on_vertices_only():
    # (1, -2**-44) lies 2**-44 below the edge 0 -> 1 (about 33 DISTround): an extreme point
    # outside the square 0 1 2 3.  The area it adds, 2 * 2**-44 / 2 = 2**-44, is within
    # Qhull's volume tolerance 10 DISTround x perimeter (~8): the volumes agree, the
    # extreme vertices do not (4 against Qhull's 5).
    h = 2.0**-44
    pts = np.array(_SQUARE + [[1.0, -h]])
    assert h <= 10 * _DR_SQUARE * 8.0
    v = check(pts, [0, 1, 2, 3])
    outside = h / _DR_SQUARE
    assert v.qhull_agreement == "disagree" and v.qhull_ok is True
    assert v.offending == {"containment": (4,), "missing_extreme": (4,)}
    assert v.detail == (
        f"containment: 1 points outside (max {outside:.3g} DISTround); "
        "extreme points: 1 missing; qhull: 4 extreme vertices against Qhull's 5"
    )
    assert v.max_violation == pytest.approx(outside, rel=1e-9)
    assert v.severity == "gross"  # 33 > 10 DISTround


def test_the_outside_magnitude_is_reported_with_containment_only():
    # The square walked twice with a point outside: containment, convexity and
    # manifoldness all fail; only the containment reason carries the DISTround magnitude
    # of the point outside, 1 / DISTround (the point (1, -1) is 1 below the edge 0 -> 1).
    pts = np.array(_SQUARE + [[1.0, -1.0]])
    v = check(pts, [0, 1, 2, 3, 0, 1, 2, 3])
    assert not v.containment and not v.convexity and not v.manifoldness
    parts = {p.split(": ", 1)[0]: p for p in v.detail.split("; ") if ": " in p}
    assert parts["containment"] == f"containment: 1 points outside (max {1.0 / _DR_SQUARE:.3g} DISTround)"
    assert v.detail.count("DISTround") == 1


def test_the_volume_is_unscaled_exactly():
    # The same walk on the square scaled by 2**200: the checker works on a copy scaled by a
    # power of two (exact) and reports the volumes in the input's units: 8 * 2**400 and
    # 4 * 2**400, exactly; every relative magnitude is the same as at unit scale.
    s = 2.0**200
    v = check(np.array(_SQUARE) * s, [0, 1, 2, 3, 0, 1, 2, 3])
    assert v.volume == 2.0**403 and v.qhull_volume == 2.0**402
    assert v.distround == pytest.approx(_DR_SQUARE * s, rel=1e-12)
    assert v.max_violation == pytest.approx(4.0 / (8.0 * _DR_SQUARE), rel=1e-9)


# The tetrahedron (0, 0, 0), (2, 0, 0), (0, 2, 0), (0, 0, 2), outward, and the point (1, 1, 1)
# beyond its slanted face x + y + z = 2: all five points are extreme.
_TET_POINTS = [[0.0, 0, 0], [2, 0, 0], [0, 2, 0], [0, 0, 2], [1, 1, 1]]
_TET = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]


def test_without_qhull_the_extreme_set_is_still_exact():
    # qhull=False: no reference, no agreement; the extreme points come from the exact
    # monotone chain (2D) or from the hull's vertices and the points outside it (3D).
    v = check(np.array(_TET_POINTS), _TET, qhull=False)
    assert (v.qhull_agreement, v.qhull_volume, v.qhull_options, v.qhull_ok) == (None, None, None, None)
    assert v.n_extreme == 5 and v.n_missing_extreme == 1
    assert v.offending == {"containment": (4,), "missing_extreme": (4,)}
    assert v.n_outside == 1 and v.n_boundary_nonextreme == 0 and v.n_hull_vertices == 4
    assert v.volume == pytest.approx(8 / 6, rel=1e-12)  # a third of base 2 x height 2
    assert v.detail.endswith("; extreme points: 1 missing")
    # 2D: the square and (1, -1) below its edge 0 -> 1, all five extreme.
    v = check(np.array(_SQUARE + [[1.0, -1.0]]), [0, 1, 2, 3], qhull=False)
    assert v.qhull_agreement is None and v.qhull_volume is None
    assert v.n_extreme == 5 and v.n_missing_extreme == 1
    assert v.offending == {"containment": (4,), "missing_extreme": (4,)}
    assert v.detail == f"containment: 1 points outside (max {1.0 / _DR_SQUARE:.3g} DISTround); extreme points: 1 missing"


def test_with_neither_hull_certified_in_3d_the_extreme_set_is_unknown():
    # Module docstring: "in 3D with neither hull certified it is unknown (n_extreme=None)".
    # A reference in that state (Qhull's hull failing the exact checks, no certified
    # extreme set): nothing is counted as missing and no repair is tried here.
    pts = np.array(_TET_POINTS)
    ref = dataclasses.replace(qhull_reference(pts), _extreme=None, qhull_ok=False, memo={})
    assert ref.extreme is None
    v = check(pts, _TET, reference=ref)
    assert v.qhull_agreement == "qhull-wrong" and v.qhull_ok is False
    assert v.n_extreme is None and v.n_missing_extreme == 0 and v.n_boundary_nonextreme == 0
    assert v.offending == {"containment": (4,)}
    assert "extreme points" not in v.detail
    assert v.detail.endswith("; qhull agreement not judged: Qhull's own hull fails the exact checks")


# --------------------------------------------------------------------------- the detail line


def test_a_passing_hull_says_ok_with_its_counts():
    # "ok: <hull vertices> vertices, <faces> faces" (3D) or "... edges" (2D).
    assert check(np.array(_SQUARE), [0, 1, 2, 3]).detail == "ok: 4 vertices, 4 edges"
    assert check(np.array(_SQUARE), [0, 1, 2, 3], qhull=False).detail == "ok: 4 vertices, 4 edges"
    tet = np.array(_TET_POINTS[:4])
    assert check(tet, _TET).detail == "ok: 4 vertices, 4 faces"
    assert check(tet, _TET, qhull=False, reuse_reference=False).detail == "ok: 4 vertices, 4 faces"
    # A passing hull judged while Qhull's own hull fails: the note follows the counts.
    ref = dataclasses.replace(qhull_reference(tet), _extreme=None, qhull_ok=False, memo={})
    v = check(tet, _TET, reference=ref)
    assert v.ok and v.qhull_agreement == "qhull-wrong"
    assert v.detail == "ok: 4 vertices, 4 faces; qhull agreement not judged: Qhull's own hull fails the exact checks"


def test_each_magnitude_goes_with_its_own_check():
    # The square [0, 4]^2 dented at the top: 0 1 2 4 3 with 4 = (2, 3).  Vertex 4 is reflex:
    # the next vertex (0, 4) is right of the line (4, 4) -> (2, 3) by 4 / sqrt(5); and the
    # corners 2 and 3 are outside the edges 4 -> 3 and 2 -> 4, by 4 / sqrt(5) each.
    pts = np.array([[0.0, 0], [4, 0], [4, 4], [0, 4], [2, 3]])
    v = check(pts, [0, 1, 2, 4, 3])
    assert not v.containment and not v.convexity and v.manifoldness
    assert v.offending["containment"] == (2, 3) and v.offending["reflex_vertices"] == (4,)
    dr = _distround(4.0, 8.0, 2)
    m = f"{4 / math.sqrt(5) / dr:.3g}"
    assert v.detail.startswith(
        f"containment: 2 points outside (max {m} DISTround); convexity: 1 reflex vertices (max {m} DISTround)"
    )
    assert v.detail.count("DISTround") == 2


# --------------------------------------------------------------------------- arguments


def test_validate_points_gives_float64_and_names_the_problem():
    from hullstress.checker.api import validate_points

    got = validate_points([[0, 1], [2, 3]])
    assert got.dtype == np.float64 and got.tolist() == [[0.0, 1.0], [2.0, 3.0]]
    with pytest.raises(ValueError, match=r"^points must be a numeric array of shape \(n, 2\) or \(n, 3\): "):
        validate_points([["a", "b"], ["c", "d"]])
    with pytest.raises(ValueError, match=r"^points must be finite, got \[1\.0, inf\] at row 2$"):
        validate_points([[0.0, 0.0], [1.0, 1.0], [1.0, np.inf], [np.nan, 0.0]])


def test_a_face_set_is_validated_like_any_output():
    from hullstress.contract import FaceSet
    from hullstress.errors import ContractViolation

    pts = np.array(_TET_POINTS[:4])
    with pytest.raises(ContractViolation, match="^a FaceSet describes a 3D surface, got 2D points$"):
        check(np.array(_SQUARE), FaceSet.from_triangles([[0, 1, 2]]))
    with pytest.raises(ContractViolation, match="^faces holds index 4, out of range for 4 points$"):
        check(pts, FaceSet.from_triangles([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 4]]))
    with pytest.raises(ContractViolation, match="^faces holds index -1, out of range for 4 points$"):
        check(pts, FaceSet.from_triangles([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, -1]]))
    with pytest.raises(ContractViolation, match=r"^face 1 has 2 vertices; a face needs at least 3 \(fewer only in the answer for a collinear or one-point input\)$"):
        check(pts, FaceSet.from_polygons([[0, 2, 1], [0, 1], [0, 3, 2], [1, 2, 3]]))
    # A valid FaceSet is judged like the same faces as a list.
    assert check(pts, FaceSet.from_triangles(_TET)).ok


def test_a_reference_for_other_points_is_refused():
    pts = np.array(_SQUARE)
    with pytest.raises(ValueError, match=r"^reference was computed for 5 points in 2D, got 4 points in 2D$"):
        check(pts, [0, 1, 2, 3], reference=qhull_reference(np.array(_SQUARE + [[1.0, 1.0]])))
    with pytest.raises(ValueError, match=r"^reference was computed for 4 points in 3D, got 4 points in 2D$"):
        check(pts, [0, 1, 2, 3], reference=qhull_reference(np.array(_TET_POINTS[:4])))
    moved = pts + np.array([0.0, 1.0])
    with pytest.raises(ValueError, match=r"^reference was computed for other points \(same shape, different coordinates\)$"):
        check(pts, [0, 1, 2, 3], reference=qhull_reference(moved))
    # The same coordinates in another array are the same points.
    assert check(pts, [0, 1, 2, 3], reference=qhull_reference(pts.copy())).ok


def test_max_offending_bounds_every_list():
    # The 6 x 6 lattice [0, 5]^2 and the triangle (0, 0), (1, 0), (0, 1): every lattice
    # point but those three is outside it (33), and three corners are missing.
    pts = np.array([[x, y] for y in range(6) for x in range(6)], dtype=np.float64)
    v = check(pts, [0, 1, 6])
    assert v.n_outside == 33
    assert v.offending["containment"] == tuple(i for i in range(36) if i not in (0, 1, 6))[:20]  # the default
    assert v.offending["missing_extreme"] == (5, 30, 35)
    assert check(pts, [0, 1, 6], max_offending=2).offending["containment"] == (2, 3)
    # Flat input: the lower-dimensional judge gets the same bound.  The points (i, i),
    # i = 0..4, answered by [0, 1]: 2, 3 and 4 are left outside.
    line = np.array([[float(i), float(i)] for i in range(5)])
    assert check(line, [0, 1]).offending["containment"] == (2, 3, 4)
    assert check(line, [0, 1], max_offending=1).offending["containment"] == (2,)


def test_a_reference_given_for_flat_input_is_recorded():
    # lowdim: the reference is "only recorded (options, Qhull's own health)".
    line = np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]])
    ref = qhull_reference(line)
    v = check(line, [0, 2], reference=ref)
    assert v.ok and v.qhull_agreement is None and v.affine_rank == 1
    assert (v.qhull_options, v.qhull_ok, v.qhull_volume) == (ref.options, ref.qhull_ok, ref.volume)
    assert v.qhull_options is not None


def test_verdicts_on_qhulls_own_faces_do_not_share_their_offending_dict():
    # The verdict on Qhull's own faces is kept on the reference and handed out as a copy
    # "with a fresh offending dict": writing into one verdict's dict leaves the next alone.
    pts = np.array(_TET_POINTS[:4])
    ref = qhull_reference(pts)
    first = check(pts, _TET, reference=ref)
    second = check(pts, _TET, reference=ref)
    assert first.ok and first.offending == {} and first.offending is not second.offending
    first.offending["containment"] = (0,)
    assert check(pts, _TET, reference=ref).offending == {}
