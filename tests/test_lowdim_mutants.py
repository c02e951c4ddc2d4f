"""The lower-dimensional judge's full verdict, field by field (docs/lower-dimensional.md).

tests/test_lowdim.py asks which check fails; these tests pin what a user reads
besides: the offending indices under their documented keys
(:func:`~hullstress.checker.lowdim.judge_lower_dimensional`), the counts, the
key words of each reason, and which points are left outside a wrong answer.
They were written against the mutants that survived tests/test_lowdim.py
(tools/mutation.sh); every expectation is derived by hand from the geometry or,
for the points outside an answer, by an independent rational computation
(tests/_exact_verdict.py), never copied from the checker.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from hullstress.checker._geometry import distround
from hullstress.checker.lowdim import judge_lower_dimensional, verdict_if_degenerate

from _exact_verdict import hull2d, to_integers, turn


def _tilted(xy) -> np.ndarray:
    """Planar 2D coordinates lifted exactly onto the plane z = x + 2y + 1 (dyadic inputs stay exact)."""
    xy = np.asarray(xy, dtype=np.float64)
    return np.c_[xy, xy[:, 0] + 2 * xy[:, 1] + 1]


def _square(*extra) -> np.ndarray:
    """Square 0..3 counter-clockwise, edge midpoint 4 on 0-1, centre 5, then ``extra`` points."""
    xy = [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0], [1.0, 0.0], [1.0, 1.0], *extra]
    return _tilted(xy)


def _judge(points, faces, **kw):
    return judge_lower_dimensional(np.asarray(points, dtype=np.float64), faces, max_offending=10**6, **kw)


def _pentagon() -> np.ndarray:
    # A convex pentagon with integer corners (counter-clockwise) and its centre (5).
    return _tilted([[0.0, 0.0], [4.0, 0.0], [5.0, 3.0], [2.0, 5.0], [-1.0, 3.0], [2.0, 2.0]])


# ----------------------------------------------------------------------------- faces of a flat input

def test_a_reflex_face_in_an_exact_tiling_is_not_convex():
    # Point 6 lies inside triangle 0 1 2, so face [0, 1, 2, 6] has a reflex corner at 6; with the convex
    # [0, 6, 2, 3] it tiles the square exactly, so only the face check can reject it.  Its turns are all
    # counter-clockwise but one, its vertices never change direction along x more than twice, and it has
    # no spike: neither of those other tests flags it.
    pts = _square([1.25, 0.75])
    faces = [[0, 1, 2, 6], [0, 6, 2, 3]]
    v = _judge(pts, faces)
    assert v.failed_checks == ("convexity",), v.detail
    assert v.offending == {"nonconvex_faces": (0,)}
    assert "face 0 is not a convex polygon" in v.detail
    assert v.n_degenerate_faces == 1 and v.n_nonconvex_edges == 0
    # The same tiling seen from the other side: the reflex face is clockwise with one counter-clockwise turn.
    back = _judge(pts, [f[::-1] for f in faces])
    assert back.failed_checks == ("convexity",) and back.offending == {"nonconvex_faces": (0,)}, back.detail
    # Control: the two convex triangles of the same diagonal pass.
    assert _judge(pts, [[0, 1, 2], [0, 2, 3]]).ok


def test_a_star_face_that_winds_twice_is_not_convex():
    # The pentagram 0 2 4 1 3 turns left at every corner, but winds twice: not a convex polygon, and a bad
    # face ends the judgement (no boundary walk is reported for it).
    v = _judge(_pentagon(), [[0, 2, 4, 1, 3]])
    assert v.failed_checks == ("convexity",), v.detail
    assert v.offending == {"nonconvex_faces": (0,)}
    assert v.n_degenerate_faces == 1 and v.n_nonconvex_edges == 0
    assert "convexity: face 0 is not a convex polygon" in v.detail and "boundary" not in v.detail


def test_a_face_of_zero_area_is_reported_by_index():
    v = _judge(_square(), [[0, 1, 2, 3], [0, 4, 1]])
    assert v.failed_checks == ("convexity",)
    assert v.offending == {"degenerate_faces": (1,)} and v.n_degenerate_faces == 1
    assert "face 1 has no area (collinear vertices)" in v.detail


def test_a_face_that_repeats_a_point_through_a_duplicate_row():
    # Row 6 has the coordinates of row 0: face 1 visits that point twice.
    v = _judge(_square([0.0, 0.0]), [[0, 1, 2, 3], [3, 2, 1, 6, 0]])
    assert v.failed_checks == ("manifoldness",), v.detail
    assert v.offending == {"manifold_faces": (1,)} and v.n_degenerate_faces == 1
    assert "face 1 repeats a point" in v.detail and v.severity == "gross"


# ----------------------------------------------------------------------------- sides that do not tile

def test_a_face_given_twice_crosses_its_edges_twice():
    tri = _tilted([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    v = _judge(tri, [[0, 1, 2], [0, 1, 2]])
    assert v.failed_checks == ("manifoldness",), v.detail
    assert v.offending == {"manifold_faces": (0, 1)}
    assert "the counter-clockwise faces do not tile the polygon: its faces overlap" in v.detail
    assert _judge(tri, [[0, 1, 2], [2, 1, 0]]).ok  # control: the face and its reverse


def test_faces_meeting_at_one_point_are_not_a_simple_boundary():
    v = _judge(_square(), [[0, 1, 5], [2, 3, 5]])
    assert v.failed_checks == ("manifoldness",), v.detail
    assert v.offending == {"manifold_faces": (0, 1)}
    assert "its boundary is not a simple cycle" in v.detail


def test_two_separate_faces_leave_two_boundary_cycles():
    # Two disjoint triangles of a hexagon (corners 0..5): every corner is used, the boundary is two cycles.
    hexagon = _tilted([[2.0, 0.0], [4.0, 1.0], [4.0, 3.0], [2.0, 4.0], [0.0, 3.0], [0.0, 1.0]])
    v = _judge(hexagon, [[0, 1, 2], [3, 4, 5]])
    assert v.failed_checks == ("manifoldness",), v.detail
    assert v.offending == {"manifold_faces": (0, 1)}
    assert "its boundary is more than one cycle" in v.detail


def test_each_side_is_judged_and_blamed_on_its_own_faces():
    # Clockwise faces only: the polygon and half of it again overlap.
    holed = _judge(_square(), [[0, 3, 2, 1], [2, 1, 0]])  # cw polygon (a full side) + a cw half: overlap
    assert holed.failed_checks == ("manifoldness",), holed.detail
    assert "the clockwise faces do not tile the polygon" in holed.detail
    assert holed.offending == {"manifold_faces": (0, 1)}
    # A good counter-clockwise side and a clockwise side with a hole: only the clockwise faces are blamed.
    v = _judge(_square(), [[0, 1, 2], [0, 2, 3], [0, 2, 1]])
    assert v.failed_checks == ("manifoldness",), v.detail
    assert v.offending == {"manifold_faces": (2,)}
    assert "the clockwise faces do not tile the polygon: their boundary misses extreme point 3 (a hole)" in v.detail
    assert "counter-clockwise faces do not" not in v.detail
    # Both sides wrong in different ways: both are reported, each with its own faces.
    both = _judge(_square(), [[0, 1, 2], [0, 1, 2], [0, 2, 3], [0, 3, 2], [0, 2, 1], [0, 2, 1], [0, 3, 2]])
    assert both.failed_checks == ("manifoldness",), both.detail
    assert "the counter-clockwise faces do not tile the polygon: its faces overlap" in both.detail
    assert "the clockwise faces do not tile the polygon: its faces overlap" in both.detail
    assert both.offending == {"manifold_faces": tuple(range(7))}
    hole_then_overlap = _judge(_square(), [[0, 1, 2], [0, 2, 1], [0, 3, 2], [0, 3, 2]])
    assert "the counter-clockwise faces do not tile the polygon: their boundary misses extreme point 3" \
        in hole_then_overlap.detail
    assert "the clockwise faces do not tile the polygon: its faces overlap" in hole_then_overlap.detail
    assert hole_then_overlap.offending == {"manifold_faces": (0, 1, 2, 3)}


def test_a_boundary_through_an_inner_point_on_both_sides():
    # The fan 0-1-2, 0-2-6, 0-6-3 covers the square minus triangle 2 6 3 (6 is inside, above the centre):
    # its boundary runs 2 -> 6 -> 3, off the hull edge 2-3.  The reversed fan is the other side, same fault.
    ccw = [[0, 1, 2], [0, 2, 6], [0, 6, 3]]
    v = _judge(_square([1.0, 1.5]), ccw + [f[::-1] for f in ccw])
    # A side that leaves part of the polygon uncovered has a hole (docs/lower-dimensional.md): manifoldness, gross.
    assert v.failed_checks == ("manifoldness",) and v.severity == "gross", v.detail
    assert v.offending == {"misordered_vertices": (6,)}
    assert v.n_nonconvex_edges == 2  # one misplaced point per side
    assert ("manifoldness: the counter-clockwise faces do not tile the polygon: their boundary: points 6 of the "
            "walk are not on the hull edge they sit between; the clockwise faces do not tile") in v.detail


def test_a_boundary_that_winds_twice_visits_the_corners_out_of_order():
    # Six counter-clockwise triangles fanned around O (3) whose rim winds twice around a triangle:
    # A (0) -> p1 (4) -> C (2) -> p2 (5) -> B (1) -> p3 (6) -> A.  The spokes cancel; the rim holds every
    # corner once but in clockwise order A, C, B.
    pts = _tilted([[0.0, 0.0], [8.0, 0.0], [0.0, 8.0], [2.0, 2.0], [6.0, 1.0], [1.0, 0.5], [0.5, 6.0]])
    rim = [0, 4, 2, 5, 1, 6]
    fan = [[3, rim[i], rim[(i + 1) % 6]] for i in range(6)]
    v = _judge(pts, fan)
    assert v.failed_checks == ("manifoldness",), v.detail  # parts of the triangle are covered twice
    assert v.offending == {"misordered_vertices": (0, 1, 2)} and v.n_nonconvex_edges == 3
    assert "the extreme points are not in order around the polygon" in v.detail
    # The same with a pentagram rim around a pentagon's centre.
    star = [0, 2, 4, 1, 3]
    v = _judge(_pentagon(), [[5, star[i], star[(i + 1) % 5]] for i in range(5)])
    assert v.failed_checks == ("manifoldness",), v.detail
    assert v.offending == {"misordered_vertices": (0, 1, 2, 3, 4)}
    assert "the extreme points are not in order around the polygon" in v.detail


def test_no_faces_for_a_flat_input_misses_every_corner():
    v = _judge(_square(), np.zeros((0, 3), dtype=np.int64))
    assert v.failed_checks == ("containment",), v.detail
    assert v.offending == {"containment": tuple(range(6)), "missing_extreme": (0, 1, 2, 3)}
    assert v.detail.endswith("; containment: extreme point 0, 1, 2, 3 missing")
    assert v.max_violation == float("inf") and v.severity == "gross"


# ----------------------------------------------------------------------------- walks (2D, and 3D segments)

def test_a_repeated_point_is_named_once():
    seg = np.array([[0.0, 0.0], [1.0, 2.0], [2.0, 4.0], [3.0, 6.0]])
    v = _judge(seg, [0, 3, 0])
    assert v.failed_checks == ("manifoldness",)
    assert v.offending == {"repeated_vertices": (0,)}
    assert "manifoldness: point 0 appears more than once" in v.detail


def test_inner_points_out_of_order_are_counted_and_named():
    seg = np.array([[0.0, 0.0], [1.0, 2.0], [2.0, 4.0], [3.0, 6.0]])
    # On the way out, the step 2 -> 1 runs backwards: point 2 is where the walk goes wrong.
    v = _judge(seg, [0, 2, 1, 3])
    assert v.failed_checks == ("convexity",)
    assert v.offending == {"misordered_vertices": (2,)} and v.n_nonconvex_edges == 1
    assert "convexity: the vertices do not run in order along the hull's edges (" in v.detail


def test_order_along_an_axis_parallel_segment_uses_every_coordinate():
    # On a horizontal line only x orders the points; on a vertical one only y.
    horizontal = np.array([[0.0, 5.0], [2.0, 5.0], [1.0, 5.0], [3.0, 5.0]])
    assert _judge(horizontal, [0, 2, 1, 3]).ok
    assert _judge(horizontal, [0, 1, 2, 3]).failed_checks == ("convexity",)
    vertical = horizontal[:, ::-1].copy()
    assert _judge(vertical, [0, 2, 1, 3]).ok
    assert _judge(vertical, [0, 1, 2, 3]).failed_checks == ("convexity",)


def test_a_duplicate_of_an_answered_point_is_not_outside():
    # Rows 1 and 2 are one point; the answer [0, 1] misses endpoint 3 only, so only row 3 is outside.
    seg = np.array([[0.0, 0.0], [1.0, 1.0], [1.0, 1.0], [2.0, 2.0]])
    v = _judge(seg, [0, 1])
    assert v.offending == {"containment": (3,), "missing_extreme": (3,)} and v.n_outside == 1
    assert v.n_hull_vertices == 2 and v.n_missing_extreme == 1 and v.n_boundary_nonextreme == 1


def test_several_faces_for_a_segment_blame_all_but_the_first():
    seg3 = np.array([[0.5, 1.0, 1.5], [0.0, 0.0, 0.0], [2.0, 4.0, 6.0], [1.0, 2.0, 3.0]])
    v = _judge(seg3, [[1, 2], [1, 3], [0, 2]])
    assert v.failed_checks == ("manifoldness",), v.detail
    assert v.offending == {"manifold_faces": (1, 2)}
    assert "manifoldness: 3 faces; a point or a segment is one face" in v.detail
    empty = _judge(seg3, np.zeros((0, 3), dtype=np.int64))
    assert empty.failed_checks == ("containment",)
    assert empty.offending == {"containment": (0, 1, 2, 3), "missing_extreme": (1, 2)}
    assert "containment: the answer has no vertices" in empty.detail


def test_an_empty_2d_answer_has_no_vertices():
    v = _judge(np.array([[0.0, 0.0], [1.0, 2.0], [2.0, 4.0]]), [])
    assert v.failed_checks == ("containment",) and "containment: the answer has no vertices" in v.detail
    assert v.offending == {"containment": (0, 1, 2), "missing_extreme": (0, 2)} and v.n_faces == 0


# ----------------------------------------------------------------------------- the reason and the record

def test_descriptions_of_each_rank():
    assert _judge(np.zeros((0, 2)), []).detail == "ok: no points: the hull is empty"
    one = _judge(np.full((3, 2), 0.5), [2])
    assert one.detail == "ok: all points are one point: the hull is point 0 (0.5, 0.5)"
    seg = _judge(np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]), [2, 0])
    assert seg.detail == "ok: collinear input: the hull is the segment from point 0 (0.0, 0.0) to point 2 (2.0, 2.0)"
    assert not _judge(np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]), [0]).detail.startswith("ok")


@pytest.mark.parametrize("k", [12, 13])
def test_long_index_lists_are_cut_after_twelve(k):
    # k points on a parabola are all corners of their (flat) hull; an empty answer misses all of them.
    xy = np.array([[float(i), float(i * i)] for i in range(k)])
    v = _judge(_tilted(xy), np.zeros((0, 3), dtype=np.int64))
    first12 = ", ".join(map(str, range(12)))
    cut = ", ..." if k > 12 else ""
    assert f"the flat polygon with extreme points {first12}{cut} ({k}, in order)" in v.detail
    assert v.detail.endswith(f"containment: extreme point {first12}{cut} missing")


def test_the_record_of_a_lower_dimensional_verdict():
    pts = np.array([[1.0, 1.0], [np.nextafter(1.0, 2.0), 1.0], [1.0, 1.0]])
    reference = SimpleNamespace(volume=0.25, options="Qt QJ", qhull_ok=False, simplex=None)
    v = judge_lower_dimensional(pts, [0], reference=reference)
    assert (v.qhull_volume, v.qhull_options, v.qhull_ok) == (0.25, "Qt QJ", False)
    assert v.qhull_agreement is None and v.volume == 0.0 and v.affine_rank == 1
    assert v.distround == distround(pts) > 0
    # One ulp left out: a rounding-sized miss, a positive violation within the roundoff multiple.
    assert v.severity == "roundoff" and 0 < v.max_violation <= 10
    assert v.failed_checks == ("containment",) and v.offending == {"containment": (1,), "missing_extreme": (1,)}
    assert (v.n_faces, v.n_hull_vertices, v.n_extreme, v.n_outside) == (0, 1, 2, 1)
    ok = judge_lower_dimensional(pts, [1, 2])
    assert ok.ok and ok.volume == 0.0 and ok.n_faces == 2 and ok.qhull_options is None and ok.max_violation == 0.0
    # A wrong answer names each failed check once, in the documented "check: reason" form.
    bad = _judge(_square(), [[0, 1, 2]])
    assert bad.detail.startswith("coplanar input: the hull is the flat polygon with extreme points 0, 1, 2, 3 (4, in order)"
                                 "; containment: extreme point 3 missing")


# ----------------------------------------------------------------------------- points outside a flat answer

def _outside_exactly(xy: np.ndarray, used: list[int]) -> list[int]:
    """Rows strictly outside the convex hull of rows ``used``, in integer arithmetic."""
    ints, _ = to_integers(xy.tolist())
    sub = [ints[i] for i in used]
    ring = [sub[i] for i in hull2d(sub)]

    def inside(p) -> bool:
        if len(ring) == 1:
            return p == ring[0]
        if len(ring) == 2:
            (a, b) = ring
            return turn(a, b, p) == 0 and min(a, b) <= p <= max(a, b)
        return all(turn(ring[i], ring[(i + 1) % len(ring)], p) >= 0 for i in range(len(ring)))

    return [i for i, p in enumerate(ints) if not inside(p)]


def _embed(xy: np.ndarray, how: int) -> np.ndarray:
    """The plane of the points, chosen so that each of the judge's three projections is needed."""
    x, y = xy[:, 0], xy[:, 1]
    if how == 0:
        return _tilted(xy)
    if how == 1:
        return np.c_[x, x, y]  # the vertical plane y = x: the (x, y) projection is a line
    return np.c_[x, np.full_like(x, 5.0), y]  # y = 5: only (x, z) keeps the points apart


@pytest.mark.parametrize("seed", range(12))
def test_points_outside_a_wrong_flat_answer_agree_with_rational_arithmetic(seed):
    rng = np.random.default_rng(seed)
    xy = rng.integers(-4, 5, size=(24, 2)).astype(np.float64) / 2
    while len({tuple(p) for p in xy}) < 3 or hull2d(to_integers(xy.tolist())[0]).__len__() < 3:
        xy = rng.integers(-4, 5, size=(24, 2)).astype(np.float64) / 2
    extreme = set(hull2d(to_integers(xy.tolist())[0]))
    for trial in range(6):
        size = int(rng.integers(3, 12))
        used = [int(i) for i in rng.choice(len(xy), size=size, replace=False)]
        if trial == 0:  # collinear answers: three points of one row or column of the grid
            used = list(range(3))
            xy[:3] = [[0.0, -1.5], [0.0, 0.5], [0.0, 2.0]] if seed % 2 else [[-1.0, 1.0], [-1.0, 1.0], [-1.0, 1.0]]
            extreme = set(hull2d(to_integers(xy.tolist())[0]))
        size = len(used)
        coords = {tuple(xy[i]) for i in used}
        if all(tuple(xy[e]) in coords for e in extreme):
            continue  # nothing missing: containment is not recomputed
        faces = [used[i:i + 3] for i in range(0, size - size % 3, 3)]
        if size % 3:
            faces.append(used[-3:])
        v = _judge(_embed(xy, seed % 3), faces)
        expected = _outside_exactly(xy, used)
        assert v.offending.get("containment", ()) == tuple(expected), (used, v.detail)
        assert v.n_outside == len(expected) and not v.containment


# ----------------------------------------------------------------------------- the public entry points

def test_faceset_answers_are_validated():
    from hullstress.contract import FaceSet
    from hullstress.errors import ContractViolation

    pts = _square()
    ok = FaceSet(np.array([0, 1, 2, 3]), np.array([0, 4]))  # index 0 and the last index are in range
    assert judge_lower_dimensional(pts, ok).ok
    for bad in ([0, 1, 6], [-1, 1, 2]):
        with pytest.raises(ContractViolation, match=r"faces holds index (6|-1), out of range for 6 points"):
            judge_lower_dimensional(pts, FaceSet(np.array(bad), np.array([0, 3])))
    with pytest.raises(ContractViolation, match="a FaceSet describes a 3D surface, got 2D points"):
        judge_lower_dimensional(pts[:, :2][[0, 4, 1]], FaceSet(np.array([0, 1, 2]), np.array([0, 3])))


def test_offending_lists_are_cut_at_max_offending():
    # 30 points on a line, the answer [0, 1]: the 28 others lie beyond point 1.
    line = np.c_[np.arange(30.0), 2 * np.arange(30.0)]
    v = judge_lower_dimensional(line, [0, 1])
    assert v.n_outside == 28 and v.offending["containment"] == tuple(range(2, 22))  # the default, 20
    assert judge_lower_dimensional(line, [0, 1], max_offending=3).offending["containment"] == (2, 3, 4)
    w = verdict_if_degenerate(line, [0, 1])
    assert w.offending["containment"] == tuple(range(2, 22))
    assert verdict_if_degenerate(line, [0, 1], max_offending=2).offending == {"containment": (2, 3), "missing_extreme": (29,)}


def test_verdict_if_degenerate_records_the_reference():
    line = np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]])
    reference = SimpleNamespace(volume=None, options="QJ", qhull_ok=True, simplex=np.array([0, 2]))
    v = verdict_if_degenerate(line, [2, 0], reference=reference)
    assert v.ok and v.qhull_options == "QJ" and v.qhull_ok is True and v.affine_rank == 1
    assert verdict_if_degenerate(np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]), [0, 1, 2]) is None


def test_integer_and_list_input_is_judged_as_floats():
    assert judge_lower_dimensional([[0, 0], [1, 1], [2, 2]], [0, 2]).ok
    assert verdict_if_degenerate([[0, 0], [1, 1], [2, 2]], [0, 2]).ok
    assert not judge_lower_dimensional([[0, 0], [1, 1], [2, 2]], [0, 1]).ok


def test_the_hull_of_nothing_and_of_a_line_falling_to_the_right():
    empty = judge_lower_dimensional(np.zeros((0, 3)), [])
    assert empty.ok and empty.affine_rank == -1 and empty.n_extreme == 0
    # The endpoints are ordered lexicographically (x first), whatever the line's slope.
    falling = np.array([[3.0, 0.0], [1.0, 2.0], [0.0, 3.0], [2.0, 1.0]])
    from hullstress.checker.lowdim import lower_dimensional_hull
    assert lower_dimensional_hull(falling).extreme.tolist() == [2, 0]
    assert "the segment from point 2 (0.0, 3.0) to point 0 (3.0, 0.0)" in judge_lower_dimensional(falling, [0, 2]).detail


def test_a_flat_input_in_a_plane_of_constant_x():
    # Only the (y, z) projection keeps these points apart.
    pts = np.c_[np.full(4, 5.0), [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]]]
    assert judge_lower_dimensional(pts, [[0, 1, 2, 3]]).ok
    v = judge_lower_dimensional(pts, [[0, 1, 2]])
    assert v.offending == {"containment": (3,), "missing_extreme": (3,)}
