"""Tests for hullstress.algorithms.henckel (seed 001, John Henckel's direct convex hull).

Hull properties are checked with an exact orientation predicate (a float
filter with Shewchuk's orient3d bound, Fractions for the undecided cases) and
against scipy's Qhull.  The seed's own rules are checked through the private
trace: the initial edge's tie rules (with a scripted random direction), the
angular sort of polygon faces, the edge and to-do lists, the tolerance
reading, and the documented failures on faces with collinear or interior
points.
"""

from __future__ import annotations

import itertools
import time
from collections import Counter

import numpy as np
import pytest
from hypothesis import example, given, note
from hypothesis import strategies as st
from scipy.spatial import ConvexHull

from hullstress import _registry
from hullstress.algorithms import henckel
from hullstress.algorithms.henckel import _find_face, _henckel_trace, _initial_edge, _ToDoList, henckel_hull
from hullstress.errors import AlgorithmStepLimit
from hullstress.tolerance import tolerance

from _hull_oracle import orient_sign, random_cloud

TET = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
CUBE = np.array(list(itertools.product((0.0, 1.0), repeat=3)))
GRID3 = np.array(list(itertools.product((0.0, 1.0, 2.0), repeat=3)))
# A 2x2x2 cube's corners and edge midpoints: faces with collinear boundary points, no interior ones.
CUBE_MIDPOINTS = np.array([p for p in itertools.product((0.0, 1.0, 2.0), repeat=3) if p.count(1.0) <= 1])


# --------------------------------------------------------------------------- helpers


class ScriptedRng:
    """Stands in for numpy's Generator: hands out the given vectors as "random" directions."""

    def __init__(self, vectors):
        self._vectors = [np.asarray(v, dtype=float) for v in vectors]

    def standard_normal(self, size):
        assert size == 3
        return self._vectors.pop(0)


def corner_triangles(faces) -> np.ndarray:
    """Every consecutive triple (u, v, w) of every polygon, as triangles."""
    return np.array([(f[i - 1], f[i], f[(i + 1) % len(f)]) for f in faces for i in range(len(f))])


def assert_closed_outward_hull(points: np.ndarray, faces, *, interior=None) -> None:
    """Closed and consistently oriented, nothing outside, Qhull's vertices; convex corners if ``interior``."""
    directed = Counter((f[i], f[(i + 1) % len(f)]) for f in faces for i in range(len(f)))
    assert max(directed.values()) == 1, "a directed edge is used twice"
    missing = [e for e in directed if (e[1], e[0]) not in directed]
    assert not missing, f"edges without a twin (surface not closed): {missing[:5]}"
    fan = np.array([(f[0], f[i], f[i + 1]) for f in faces for i in range(1, len(f) - 1)])
    assert (orient_sign(points, fan, points) >= 0).all(), "a point lies outside a face"
    assert {i for f in faces for i in f} == set(ConvexHull(points).vertices.tolist())
    if interior is not None:
        # Every corner turns counter-clockwise seen from outside: convex polygons, outward.
        assert (orient_sign(points, corner_triangles(faces), np.array([interior])) > 0).all()


def seed_sort_key(points: np.ndarray, a: int, b: int, members) -> np.ndarray:
    """The seed's angle(P) = (P - B).(A - B), divided by |P - B| (the module's reading)."""
    rel = points[members] - points[b]
    return (rel @ (points[a] - points[b])) / np.linalg.norm(rel, axis=1)


# --------------------------------------------------------------------------- registration and contract


def test_registered_as_henckel():
    spec = _registry.get_algorithm("henckel")
    assert spec.func is henckel_hull
    assert spec.dim == 3 and spec.takes_eps and spec.origin == "in-house"


def test_returns_polygons_of_ints_and_leaves_input_alone():
    pts = random_cloud(1, 50, "ball")
    pts.setflags(write=False)
    before = pts.copy()
    faces = henckel_hull(pts)
    assert isinstance(faces, list) and all(isinstance(f, list) for f in faces)
    assert all(type(i) is int for f in faces for i in f)
    np.testing.assert_array_equal(pts, before)


@pytest.mark.parametrize(
    ("points", "eps", "message"),
    [
        (np.zeros((5, 2)), None, r"points must have shape \(n, 3\), got \(5, 2\)"),
        (np.zeros(9), None, r"points must have shape \(n, 3\), got \(9,\)"),
        (TET[:2], None, "points must hold at least 3 points, got 2"),
        (np.zeros((0, 3)), None, "points must hold at least 3 points, got 0"),
        (np.vstack([TET, [[0, 0, np.nan]]]), None, r"points must be finite, got \[0.0, 0.0, nan\] at row 4"),
        (TET, -0.5, "eps must be a finite number >= 0 or None, got -0.5"),
        (TET, float("inf"), "eps must be a finite number >= 0 or None"),
        (np.c_[np.zeros((6, 2)), np.arange(6.0)], None, "step 5 found no point off the line"),
    ],
)
def test_bad_calls_raise_value_error(points, eps, message):
    with pytest.raises(ValueError, match=f"^henckel: {message}"):
        henckel_hull(points, eps=eps)


# --------------------------------------------------------------------------- hull properties


@given(
    n=st.integers(4, 200),
    seed=st.integers(0, 2**32 - 1),
    kind=st.sampled_from(["ball", "cube", "gauss"]),
    policy=st.sampled_from(["scaled", "fixed"]),
    direction_seed=st.integers(0, 2**16),
)
def test_general_position_gives_the_hull(n, seed, kind, policy, direction_seed):
    pts = random_cloud(seed, n, kind)
    faces = henckel_hull(pts, eps=tolerance(pts, policy), seed=direction_seed)
    note(f"{len(faces)} faces")
    assert all(len(f) == 3 for f in faces)  # no four points are coplanar
    assert_closed_outward_hull(pts, faces)


@pytest.mark.parametrize("scale_exp", [-30, -3, 7, 40])
def test_power_of_two_scaling_changes_nothing_under_the_scaled_policy(scale_exp):
    pts = random_cloud(5, 150, "gauss")
    assert henckel_hull(pts) == henckel_hull(pts * 2.0**scale_exp)


def test_same_seed_same_faces_other_seed_other_start():
    pts = random_cloud(6, 80, "cube")
    assert henckel_hull(pts, seed=3) == henckel_hull(pts, seed=3)
    eps = tolerance(pts, "scaled")
    t3 = _henckel_trace(pts, eps, np.random.default_rng(3))
    t4 = _henckel_trace(pts, eps, np.random.default_rng(4))
    assert not np.array_equal(t3.direction, t4.direction)
    assert_closed_outward_hull(pts, henckel_hull(pts, seed=4))


@pytest.mark.slow
@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("kind", ["ball", "gauss"])
def test_general_position_n2000(seed, kind):
    pts = random_cloud(seed, 2000, kind)
    assert_closed_outward_hull(pts, henckel_hull(pts, seed=seed))


def test_n1000_ball_runs_quickly():
    pts = random_cloud(3, 1000, "ball")
    start = time.perf_counter()
    faces = henckel_hull(pts)
    elapsed = time.perf_counter() - start
    assert {i for f in faces for i in f} == set(ConvexHull(pts).vertices.tolist())
    assert elapsed < 5.0, f"n=1000 took {elapsed:.2f} s"


# --------------------------------------------------------------------------- the initial edge and its tie rules


def test_more_than_three_points_at_the_maximum_draw_again():
    square_top = np.array([[1, 1, 1], [1, -1, 1], [-1, 1, 1], [-1, -1, 1], [0, 0, -1], [0.3, 0.2, -2]], float)
    a, b, direction, draws = _initial_edge(square_top, ScriptedRng([[0, 0, 1], [1, 0.5, 0.1]]))
    assert draws == 2 and a == 0  # (1, 1, 1) is extreme in the second direction
    np.testing.assert_allclose(direction, np.array([1, 0.5, 0.1]) / np.linalg.norm([1, 0.5, 0.1]))


def test_three_points_at_the_maximum_are_accepted_lowest_index_first():
    triangle_top = np.array([[0, 0, -2], [1, 0, 1], [0.2, 0.1, -1], [-1, 1, 1], [-0.5, -1, 1], [0.3, -0.2, -3]], float)
    a, b, _, draws = _initial_edge(triangle_top, ScriptedRng([[0, 0, 1]]))
    assert (a, draws) == (1, 1)
    # Rows 3 and 4 both lie in the plane M (sine 0); row 4 is nearer to A.
    assert b == 4


def test_equal_angles_choose_the_point_nearest_to_a():
    pts = np.array([[2, 0, -1], [0, 0, 1], [1, 0, 0], [0, 1, -3], [-1, -1, -2], [0.5, -1, -2.5]], float)
    rel = np.delete(pts - pts[1], 1, axis=0)
    sine = rel[:, 2] / np.linalg.norm(rel, axis=1)
    assert sine[0] == sine[1] == sine.max()  # rows 0 and 2 lie on one ray from A: an exact tie
    a, b, _, _ = _initial_edge(pts, ScriptedRng([[0, 0, 1]]))
    assert (a, b) == (1, 2)


def test_initial_edge_takes_the_smallest_angle_to_the_plane_and_is_a_hull_edge():
    pts = random_cloud(9, 120, "gauss")
    a, b, d, _ = _initial_edge(pts, np.random.default_rng(0))
    assert a == int(np.argmax(pts @ d))
    rel = np.delete(pts - pts[a], a, axis=0)
    sines = rel @ d / np.linalg.norm(rel, axis=1)
    assert sines.max() <= 0
    assert np.delete(np.arange(120), a)[np.argmax(sines)] == b
    hull_edges = {frozenset((s[i], s[j])) for s in ConvexHull(pts).simplices for i, j in ((0, 1), (1, 2), (0, 2))}
    assert frozenset((a, b)) in hull_edges


def test_a_duplicate_of_a_is_never_b():
    pts = np.vstack([TET, TET[3:4]])  # (0, 0, 1) twice: a tie of two at the top
    a, b, _, draws = _initial_edge(pts, ScriptedRng([[0, 0, 1]]))
    assert (a, draws) == (3, 1) and b not in (3, 4)


@pytest.mark.parametrize("points", [np.ones((10, 3)), np.repeat(TET, 4, axis=0)], ids=["all-equal", "tet-x4"])
def test_ties_of_four_everywhere_trip_the_direction_guard(points):
    with pytest.raises(AlgorithmStepLimit, match="^henckel: initial edge step 3 drew 1000 random directions"):
        henckel_hull(points)


# --------------------------------------------------------------------------- faces, edge list and to-do list


def test_cube_gives_six_convex_quadrilaterals_ordered_as_the_seed_says():
    trace = _henckel_trace(CUBE, tolerance(CUBE, "scaled"), np.random.default_rng(0))
    faces = henckel_hull(CUBE)
    assert sorted(len(f) for f in faces) == [4] * 6
    assert faces == [f[::-1] for f in trace.faces]  # the seed's clockwise lists, reversed
    assert_closed_outward_hull(CUBE, faces, interior=np.array([0.5, 0.5, 0.5]))
    for face, (a, b) in zip(trace.faces, trace.face_edges):
        assert face[0] == b and face[-1] == a  # the face closes with its own edge A -> B
        key = seed_sort_key(CUBE, a, b, face[1:])
        assert (np.diff(key) > 0).all()
    # Steps 11-12: an edge enters the edge list the first time it is met (its
    # reverse is the to-do entry), so the list holds each cube edge once.
    assert len(trace.edge_list) == 12
    assert {frozenset(e) for e in trace.edge_list} == {
        frozenset((i, j)) for i, j in itertools.combinations(range(8), 2) if np.abs(CUBE[i] - CUBE[j]).sum() == 1
    }
    assert len(trace.faces) == 6  # one face per iteration, none built twice


@given(st.lists(st.tuples(st.sampled_from(["append", "remove", "front"]), st.integers(0, 3)), max_size=60))
@example([("append", 0), ("append", 1), ("append", 0), ("remove", 0), ("front", 0)])
def test_to_do_list_behaves_like_a_python_list(ops):
    # The seed's list operations: append, "remove E" (the first copy) and
    # "get the next edge" (the front, left in place).
    model: list[tuple[int, int]] = []
    todo = _ToDoList()
    for op, k in ops:
        edge = (k, k + 1)
        if op == "append":
            model.append(edge)
            todo.append(edge)
        elif op == "remove" and edge in model:
            model.remove(edge)
            todo.remove(edge)
        elif op == "front" and model:
            assert todo.front() == model[0]
        assert len(todo) == len(model)
        assert all((edge in todo) == (edge in model) for edge in [(j, j + 1) for j in range(4)])


def test_tetrahedron_edge_and_to_do_lists():
    trace = _henckel_trace(TET, 0.0, np.random.default_rng(0))
    assert len(trace.faces) == 4 and all(len(f) == 3 for f in trace.faces)
    # Each of the six edges once, in the direction of the first face that has it.
    assert len(trace.edge_list) == 6
    assert {frozenset(e) for e in trace.edge_list} == {frozenset(p) for p in itertools.combinations(range(4), 2)}
    assert trace.face_edges[0] == trace.initial_edge
    # Every later face was built on a to-do entry: the reverse of a listed edge.
    assert all((b, a) in trace.edge_list for a, b in trace.face_edges[1:])


def test_a_3x3x3_grid_face_gathers_nine_points_in_angular_order_then_never_closes():
    eps = tolerance(GRID3, "scaled")
    a, b, _, _ = _initial_edge(GRID3, np.random.default_rng(0))
    face, _ = _find_face(GRID3, a, b, eps, 200)
    assert len(face) == 9 and face[0] == b and face[-1] == a
    plane = GRID3[face]
    assert (plane == plane[0]).all(axis=0).any()  # one coordinate is constant: a cube face
    centre = plane.mean(axis=0)
    assert any(np.array_equal(GRID3[i], centre) for i in face)  # the interior point is in the face
    key = seed_sort_key(GRID3, a, b, face[1:])
    order = sorted(range(8), key=lambda k: (key[k], face[1 + k]))  # ascending, ties by index
    assert order == list(range(8))
    # The interior point's edges enter the to-do list; faces built on them
    # (B inside the face) cannot contain A -> B, and the loop never ends.
    with pytest.raises(AlgorithmStepLimit, match=r"^henckel: steps 5-14 \(main loop\) built 208 faces"):
        henckel_hull(GRID3)


def test_collinear_boundary_points_sorted_by_index_break_the_face():
    # On the face x = 0, from B = (0, 0, 2) towards A = (0, 1, 2), the point
    # (0, 2, 2) has the same angle as A; the stable sort keeps index order and
    # puts it after A, so the face does not end with A -> B.
    b = int(np.flatnonzero((CUBE_MIDPOINTS == [0, 0, 2]).all(axis=1))[0])
    a = int(np.flatnonzero((CUBE_MIDPOINTS == [0, 1, 2]).all(axis=1))[0])
    far = int(np.flatnonzero((CUBE_MIDPOINTS == [0, 2, 2]).all(axis=1))[0])
    assert a < far
    face, _ = _find_face(CUBE_MIDPOINTS, a, b, 0.0, 200)
    assert len(face) == 8 and face[0] == b and face[-2:] == [a, far]
    with pytest.raises(AlgorithmStepLimit, match=r"^henckel: steps 5-14 \(main loop\)"):
        henckel_hull(CUBE_MIDPOINTS)


def test_on_the_plane_means_within_eps_of_the_normalised_distance():
    # A 1000-wide square base with one corner lifted by 1e-9, and an apex.
    # |NM| is about 1e6 here: compared unnormalised, the lift would be 1e-3.
    pts = np.array([[0, 0, 0], [1000, 0, 0], [1000, 1000, 1e-9], [0, 1000, 0], [500, 500, -700]], float)
    loose = henckel_hull(pts, eps=1e-6)
    tight = henckel_hull(pts, eps=0.0)
    assert sorted(len(f) for f in loose) == [3, 3, 3, 3, 4]  # the base is one quadrilateral
    assert sorted(len(f) for f in tight) == [3] * 6  # the lifted corner splits it
    assert_closed_outward_hull(pts, tight)


# --------------------------------------------------------------------------- guards and degenerate input


def test_pivot_guard_names_the_step(monkeypatch):
    monkeypatch.setattr(henckel, "_pivot_limit", lambda n: 0)
    pts = random_cloud(2, 60, "ball")
    with pytest.raises(AlgorithmStepLimit, match=r"^henckel: steps 6-8 \(pivoting\) exceeded 0 pivots"):
        henckel_hull(pts)


def test_flat_input_gives_two_faces_each_way_round():
    rng = np.random.default_rng(3)
    flat = np.c_[rng.random((60, 2)), np.zeros(60)]
    faces = henckel_hull(flat)
    assert len(faces) == 2 and all(sorted(f) == list(range(60)) for f in faces)
    # Three points: the same triangle twice, once each way round.
    front, back = henckel_hull(TET[:3])
    assert sorted(front) == sorted(back) == [0, 1, 2]
    assert back[::-1] in [front[k:] + front[:k] for k in range(3)]


@pytest.mark.parametrize(
    ("name", "outcome"),
    [
        ("tilted-flat", "faces"),
        ("near-line", "step-limit"),
        ("duplicated-cloud", "step-limit"),
        ("grid-10", "step-limit"),
        ("sphere-400", "faces"),
    ],
)
def test_degenerate_input_ends_as_documented(name, outcome):
    rng = np.random.default_rng(2)
    points = {
        "tilted-flat": np.c_[rng.random((200, 2)), np.zeros(200)] @ np.linalg.qr(rng.standard_normal((3, 3)))[0],
        "near-line": np.outer(rng.random(50), [1.0, 2.0, 3.0]),  # rounding keeps it off one exact line
        "duplicated-cloud": np.repeat(random_cloud(4, 30, "ball"), 3, axis=0),
        "grid-10": np.array(list(itertools.product(range(10), repeat=3)), dtype=float),
        "sphere-400": (lambda x: x / np.linalg.norm(x, axis=1)[:, None])(rng.standard_normal((400, 3))),
    }[name]
    start = time.perf_counter()
    if outcome == "faces":
        faces = henckel_hull(points)
        assert len(faces) >= 2
    else:
        with pytest.raises(AlgorithmStepLimit, match="^henckel: "):
            henckel_hull(points)
    assert time.perf_counter() - start < 20.0
