"""Stage attribution and status rules of ``hullstress.evaluate``, pinned where mutation testing found them loose.

``tools/mutation.sh 'hullstress.evaluate.*'`` planted one change at a time
in :mod:`hullstress.evaluate` (the module that decides a row's status and
stage from a call's outcome, docs/results-table.md and docs/design.md's
status rules); these tests kill the ones the stage tests let through: every
outcome kind with sphere on and off, the columns every row carries, the
invalid-input and degenerate rules, the case facts, and the two caches
(which must never change a verdict).
"""

from __future__ import annotations

import importlib

import numpy as np
import pytest


from hullstress._registry import ALGORITHMS, register_algorithm
from hullstress.case import Case
from hullstress.config import AlgorithmConfig
from hullstress.contract import FaceSet
from hullstress.errors import CodeCrashed, ContractViolation
from hullstress.evaluate import CallOutcome, CaseFacts, call_algorithm, case_facts, evaluate, input_problem, judge
from hullstress.records import CONTRACT_REASON, METHOD_REASON

ev = importlib.import_module("hullstress.evaluate")  # the package exports a function of that name

#: Squares of these coordinates underflow: the sphere projection finds a point with no direction.
TINY = np.random.default_rng(0).normal(size=(12, 2)) * 1e-170
SQUARE = np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0], [1.0, 1.0]])
LINE = np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]])
CUBE = np.array([[x, y, z] for x in (0.0, 1.0) for y in (0.0, 1.0) for z in (0.0, 1.0)])


def _square_hull(points):
    """The hull of SQUARE-like input: monotone chain via scipy (a correct 2D test algorithm)."""
    from scipy.spatial import ConvexHull

    return [int(i) for i in ConvexHull(points).vertices]


def _raises_memory(points):
    raise MemoryError("planted")


def _raises_value(points):
    raise ValueError("planted")


def _contract(points):
    raise ContractViolation("planted: unreadable output")


def _crashes(points):
    raise CodeCrashed("killed by SIGSEGV (planted)")


def _one_index(points):
    return [0]


def _drops_a_vertex(points):
    return _square_hull(points)[1:]


def _wants_eps(points, eps=None):
    if eps is None:
        raise AssertionError("eps was not passed")
    return _square_hull(points)


def _clockwise(points):
    return _square_hull(points)[::-1]


def _out_of_range(points):
    return [0, 1, len(points) + 5]


def _contract_eps(points, eps=None):
    raise ContractViolation("planted: unreadable output")


def _crashes_eps(points, eps=None):
    raise CodeCrashed("killed by SIGSEGV (planted)")


def _out_of_range_eps(points, eps=None):
    return [0, 1, len(points) + 5]


def _writes(points):
    points[0, 0] = 123.0  # a library that scribbles on its input
    return _square_hull(points)


NAMES = {
    "test-ev-hull": (_square_hull, {}),
    "test-ev-memory": (_raises_memory, {}),
    "test-ev-value": (_raises_value, {}),
    "test-ev-contract": (_contract, {}),
    "test-ev-crash": (_crashes, {}),
    "test-ev-one-index": (_one_index, {}),
    "test-ev-drops": (_drops_a_vertex, {}),
    "test-ev-eps": (_wants_eps, {}),
    "test-ev-writes": (_writes, {"writable": True}),
    "test-ev-writes-read-only": (_writes, {}),
    "test-ev-clockwise": (_clockwise, {"clockwise": True}),
    "test-ev-out-of-range": (_out_of_range, {}),
    "test-ev-contract-eps": (_contract_eps, {}),
    "test-ev-crash-eps": (_crashes_eps, {}),
    "test-ev-out-of-range-eps": (_out_of_range_eps, {}),
}


@pytest.fixture(scope="module", autouse=True)
def algorithms():
    for name, (func, opts) in NAMES.items():
        register_algorithm(name, dim=2, **opts)(func)
    yield
    for name in NAMES:
        ALGORITHMS.remove(name)


def _case(points: np.ndarray, dim: int = 2) -> Case:
    return Case(points=points, dim=dim, family="test-evaluate")


# --------------------------------------------------------------------------- input facts


@pytest.mark.parametrize("points, dim, expected", [
    (np.zeros((3, 3)), 2, "points have shape (3, 3), expected (n, 2)"),
    (np.zeros((3,)), 2, "points have shape (3,), expected (n, 2)"),
    (np.zeros((0, 2)), 2, "no points"),
    (np.array([[0.0, np.nan], [1.0, 1.0], [np.nan, np.inf]]), 2, "points contain NaN (2 rows)"),
    (np.array([[0.0, np.inf], [1.0, 1.0], [-np.inf, 2.0]]), 2, "points contain infinity (2 rows)"),
    (np.array([[0.0, 1.0]]), 2, None),
    (SQUARE, 2, None),
])
def test_input_problem_names_shape_emptiness_and_non_finite_rows(points, dim, expected):
    assert input_problem(points, dim) == expected


def test_points_facts_of_invalid_degenerate_and_full_dimensional_input():
    bad = ev.points_facts(np.array([[np.nan, 0.0]]), 2)
    assert bad == CaseFacts(invalid_input="points contain NaN (1 rows)", affine_rank=None, degenerate=True)
    line = ev.points_facts(LINE, 2)
    assert (line.invalid_input, line.affine_rank, line.degenerate) == (None, 1, True)
    assert line.reference is not None
    full = ev.points_facts(SQUARE, 2)
    assert (full.affine_rank, full.degenerate) == (2, False) and full.reference is not None
    bare = ev.points_facts(SQUARE, 2, qhull=False)
    assert (bare.affine_rank, bare.degenerate, bare.reference) == (2, False, None)
    # The reference is built with the options given first.
    assert case_facts(_case(CUBE, 3), qhull=False).reference is None


def test_given_facts_are_cached_per_points_dim_and_reference_and_evict_the_oldest():
    ev._GIVEN_FACTS.clear()
    first = ev._given_facts(SQUARE, 2, True)
    assert first.reference is not None and first.affine_rank == 2
    assert ev._given_facts(SQUARE.copy(), 2, True) is first
    assert ev._given_facts(SQUARE, 2, False) is not first and ev._given_facts(SQUARE, 2, False).reference is None
    for k in range(ev._GIVEN_FACTS_SIZE):
        ev._given_facts(SQUARE + k + 10.0, 2, False)
    assert len(ev._GIVEN_FACTS) == ev._GIVEN_FACTS_SIZE
    assert ev._given_facts(SQUARE, 2, True) is not first  # the oldest went first
    assert ev._given_facts(SQUARE + ev._GIVEN_FACTS_SIZE + 9.0, 2, False) is ev._given_facts(
        SQUARE + ev._GIVEN_FACTS_SIZE + 9.0, 2, False)  # the newest stayed


# --------------------------------------------------------------------------- preprocessing and the call


def test_preprocess_gives_the_algorithm_read_only_projected_points_and_the_eps():
    points, index_map, kwargs = ev._preprocess(_case(SQUARE), AlgorithmConfig("test-ev-eps", "on", "scaled"))
    assert points.dtype == np.float64 and points.flags.c_contiguous and not points.flags.writeable
    assert index_map.dtype == np.int64 and sorted(set(index_map.tolist())) <= list(range(len(SQUARE)))
    assert kwargs["eps"] > 0
    _, no_map, plain = ev._preprocess(_case(SQUARE), AlgorithmConfig("test-ev-eps", "off", "fixed"))
    assert no_map is None and plain["eps"] > 0
    assert ev._preprocess(_case(SQUARE), AlgorithmConfig("test-ev-hull"))[2] == {}


def test_preprocess_errors_name_the_step(monkeypatch):
    # A tolerance that is not finite for finite input (no input of ours overflows the formulas, so
    # the tolerance is planted): the eps set-up is to blame, not the algorithm.
    real = ev.tolerance
    monkeypatch.setattr(ev, "tolerance", lambda points, policy: np.inf)
    with pytest.raises(ev.PreprocessError, match=r"^eps set-up: the scaled tolerance is inf for finite input$"):
        ev._preprocess(_case(SQUARE), AlgorithmConfig("test-ev-eps", "off", "scaled"))
    with pytest.raises(ev.PreprocessError, match=r"^eps set-up: the \w+ tolerance is inf for finite input$"):
        ev._preprocess(_case(SQUARE), AlgorithmConfig("test-ev-eps", "on", "scaled"))
    # Non-finite input gives a non-finite eps by the seed's formula: passed on, not an error.
    nan = _case(np.array([[0.0, np.nan], [1.0, 0.0], [0.0, 1.0]]))
    assert ev._preprocess(nan, AlgorithmConfig("test-ev-eps", "off", "scaled"))[2]["eps"] == np.inf
    monkeypatch.setattr(ev, "tolerance", real)
    # A projection that raises is the method's.
    with pytest.raises(ev.PreprocessError, match=r"^sphere projection: "):
        ev._preprocess(_case(TINY), AlgorithmConfig("test-ev-hull", "on"))
    # A projection that overflows: not finite, named.
    monkeypatch.setattr("hullstress.sphere.sphere_project",
                        lambda points, eps: (np.full_like(points, np.inf), np.arange(len(points))))
    monkeypatch.setattr(ev, "_PROJECTIONS", type(ev._PROJECTIONS)())  # forget the real projection of SQUARE
    with pytest.raises(ev.PreprocessError, match=r"^sphere projection: the projected points are not finite "
                                                 r"\(the method's float arithmetic overflowed\)$"):
        ev._preprocess(_case(SQUARE), AlgorithmConfig("test-ev-hull", "on"))


def test_a_case_is_projected_once_per_duplicate_tolerance(monkeypatch):
    # Every config of a case with sphere on and the same duplicate tolerance is given the same
    # projected points: the projection runs once, its result (or its error) is handed out again.
    calls = []
    real = ev._fresh_projection

    def counting(points, eps):
        calls.append(eps)
        return real(points, eps)

    monkeypatch.setattr(ev, "_fresh_projection", counting)
    monkeypatch.setattr(ev, "_PROJECTIONS", type(ev._PROJECTIONS)())
    case = _case(SQUARE)
    first = ev._preprocess(case, AlgorithmConfig("test-ev-hull", "on"))
    again = ev._preprocess(case, AlgorithmConfig("test-ev-value", "on"))
    assert len(calls) == 1
    assert first[0] is again[0] and first[1] is again[1]
    assert not first[0].flags.writeable and not first[1].flags.writeable
    # Another tolerance (eps fixed keeps the duplicates the scaled one merges) projects again.
    ev._preprocess(case, AlgorithmConfig("test-ev-eps", "on", "fixed"))
    assert len(calls) == 2 and calls[0] != calls[1]
    # A failing projection fails the same way every time, from the one attempt.
    tiny = _case(TINY)
    messages = []
    for name in ("test-ev-hull", "test-ev-value"):
        with pytest.raises(ev.PreprocessError, match=r"^sphere projection: ") as err:
            ev._preprocess(tiny, AlgorithmConfig(name, "on"))
        messages.append(str(err.value))
    assert len(calls) == 3 and messages[0] == messages[1]
    # The memory is bounded: the oldest projections go first.
    for k in range(ev._PROJECTIONS_SIZE + 3):
        ev._preprocess(_case(SQUARE * (k + 2)), AlgorithmConfig("test-ev-hull", "on"))
    assert len(ev._PROJECTIONS) == ev._PROJECTIONS_SIZE
    seen = len(calls)
    ev._preprocess(_case(SQUARE * (ev._PROJECTIONS_SIZE + 4)), AlgorithmConfig("test-ev-hull", "on"))
    assert len(calls) == seen  # the newest is remembered
    ev._preprocess(case, AlgorithmConfig("test-ev-hull", "on"))
    assert len(calls) == seen + 1  # the oldest was forgotten
    # A NaN tolerance is never equal to itself, so it is not kept either (a tuple holding one
    # NaN object does equal itself: the test is on the tolerance, not on the key).
    before = dict(ev._PROJECTIONS)
    with pytest.raises(ev.PreprocessError):
        ev._projection(_case(SQUARE * 3.5), float("nan"))
    assert dict(ev._PROJECTIONS) == before


def test_the_sphere_methods_duplicate_tolerance_is_the_configs_policy_on_the_input(monkeypatch):
    # The square's corner (2, 2) again one ulp (2**-51) to the right, last: the scaled tolerance
    # of these points is machine epsilon times the spread of their distances from the origin,
    # 2**-52 * 2 sqrt(2), about 6.3e-16 (tolerance.py), above the 4.4e-16 gap, so the later copy
    # is a duplicate and the corner stays row 2; with no tolerance (0) the copy, further
    # right, is the support point instead.
    from hullstress.sphere import sphere_project
    from hullstress.tolerance import tolerance

    pts = np.vstack([SQUARE, [[np.nextafter(2.0, 3.0), 2.0]]])
    assert pts[5, 0] - 2.0 == 2.0**-51 < tolerance(pts, "scaled")
    assert sphere_project(pts, eps=0.0)[1].tolist() == [0, 1, 5, 3]  # not vacuous
    monkeypatch.setattr(ev, "_PROJECTIONS", type(ev._PROJECTIONS)())
    _, index_map, _ = ev._preprocess(_case(pts), AlgorithmConfig("test-ev-hull", "on"))
    assert index_map.tolist() == [0, 1, 2, 3]


def test_the_sphere_causes_of_each_duplicate_tolerance_are_its_own(monkeypatch):
    # The square with its corner (2, 2) again one ulp to the right (row 5): the input's hull
    # has the 4 corners 0, 1, 5, 3 ((2, 2) lies on the top edge).  The scaled duplicate
    # tolerance (about 6.3e-16) merges row 5 into row 2 and the projection loses one extreme
    # point; the fixed one (2**-52, below the 2**-51 gap) keeps it and loses none.  Judged one
    # after the other, each config reports the causes of its own projection.
    import hullstress.sphere_causes as sc

    monkeypatch.setattr(sc, "_CACHE", type(sc._CACHE)())
    pts = np.vstack([SQUARE, [[np.nextafter(2.0, 3.0), 2.0]]])
    case = _case(pts)
    scaled = evaluate(case, AlgorithmConfig("monotone-chain", "on", "scaled"))
    fixed = evaluate(case, AlgorithmConfig("monotone-chain", "on", "fixed"))
    assert (scaled["sphere_extreme"], scaled["sphere_lost_extreme"]) == (4, 1)
    assert (fixed["sphere_extreme"], fixed["sphere_lost_extreme"]) == (4, 0)
    assert scaled.status == "fail" and fixed.status == "pass"


def test_the_projection_uses_the_duplicate_tolerance_it_is_given_and_names_the_methods_error(monkeypatch):
    # A corner (2, 0) and a point (2.1, -0.1) just outside it, 0.14 apart: with a duplicate
    # tolerance of 0.5 the later one is a duplicate of the corner (the first of a group is
    # kept), with the default (scaled, about 6e-16) it is the hull's corner instead.
    from hullstress.sphere import sphere_project

    pts = np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0], [2.1, -0.1]])
    assert sphere_project(pts, eps=0.5)[1].tolist() == [0, 1, 2, 3]
    assert 4 in sphere_project(pts)[1].tolist()  # not vacuous: the tolerance decides
    projected, index_map = ev._fresh_projection(pts, 0.5)
    assert index_map.tolist() == [0, 1, 2, 3] and index_map.dtype == np.int64
    assert projected.dtype == np.float64 and projected.flags.c_contiguous and not projected.flags.writeable
    # The method's own exception, named with its type and message.
    def raising(points, eps):
        raise ValueError("planted failure")

    monkeypatch.setattr("hullstress.sphere.sphere_project", raising)
    assert ev._fresh_projection(pts, 0.5) == "sphere projection: ValueError: planted failure"


def test_call_outcome_kinds_and_what_they_carry():
    case = _case(SQUARE)
    ok = call_algorithm(case, AlgorithmConfig("test-ev-eps", "off", "fixed"))
    assert ok.kind == "ok" and ok.eps_value > 0 and ok.seconds >= 0 and ok.given is None
    assert ok.faces.tolist() == [0, 1, 2, 3]  # canonical: smallest index first, counter-clockwise
    raised = call_algorithm(case, AlgorithmConfig("test-ev-value"))
    assert (raised.kind, raised.error) == ("raised", "ValueError: planted")
    assert raised.frame.endswith(" in _raises_value") and raised.eps_value is None
    assert call_algorithm(case, AlgorithmConfig("test-ev-contract")).kind == "contract"
    assert call_algorithm(case, AlgorithmConfig("test-ev-crash")).error == "killed by SIGSEGV (planted)"
    # Sphere on: the outcome carries the projected points, their map and the unmapped faces.
    on = call_algorithm(case, AlgorithmConfig("test-ev-hull", "on"))
    assert on.kind == "ok" and on.given is not None and on.index_map is not None
    assert on.faces.tolist() == on.index_map[on.given_faces].tolist()
    on_raised = call_algorithm(case, AlgorithmConfig("test-ev-value", "on"))
    assert on_raised.given is not None and on_raised.index_map is not None
    # A library that writes into its input gets a copy; the case keeps its points.
    scribbled = _case(SQUARE.copy())
    assert call_algorithm(scribbled, AlgorithmConfig("test-ev-writes")).kind == "ok"
    assert scribbled.points[0, 0] == 0.0
    pre = call_algorithm(_case(TINY), AlgorithmConfig("test-ev-hull", "on"))
    assert pre.kind == "preprocess" and pre.error.startswith("sphere projection:") and pre.seconds >= 0


# --------------------------------------------------------------------------- judge: every outcome kind


def _facts(degenerate=False, invalid=None, rank=2, reference=None):
    return CaseFacts(invalid_input=invalid, affine_rank=rank, degenerate=degenerate, reference=reference)


@pytest.mark.parametrize("sphere", ["off", "on"])
@pytest.mark.parametrize("facts, status", [
    (_facts(), "error"), (_facts(degenerate=True, rank=1), "rejected"),
    (_facts(degenerate=True, invalid="no points", rank=None), "rejected"),
])
def test_a_preprocessing_failure_is_rejected_only_on_degenerate_or_invalid_input(sphere, facts, status):
    outcome = CallOutcome("preprocess", error="eps set-up: planted", seconds=0.25)
    row = judge(_case(SQUARE), AlgorithmConfig("test-ev-hull", sphere), outcome, facts)
    assert (row["status"], row["stage"], row["reason"]) == (status, "preprocess", "preprocess: eps set-up: planted")
    assert row["sphere_method"] == (status if sphere == "on" else "")
    assert (row["seconds"], row["degenerate"], row["invalid_input"]) == (0.25, facts.degenerate, facts.invalid_input or "")


@pytest.mark.parametrize("error, degenerate, status", [
    ("ValueError: planted", False, "error"),
    ("ValueError: planted", True, "rejected"),
    ("MemoryError: planted", True, "error"),  # running out of memory is no rejection
    ("RecursionError: planted", True, "error"),
    ("MemoryError: planted", False, "error"),
])
def test_an_exception_is_rejected_only_on_degenerate_input_and_never_for_resources(error, degenerate, status):
    outcome = CallOutcome("raised", error=error, seconds=0.5, eps_value=0.125, frame="lib:3 in f")
    row = judge(_case(SQUARE), AlgorithmConfig("test-ev-hull"), outcome, _facts(degenerate=degenerate))
    assert (row["status"], row["stage"], row["reason"], row["error_frame"]) == (status, "algorithm", error, "lib:3 in f")
    assert (row["seconds"], row["eps_value"], row["degenerate"]) == (0.5, 0.125, degenerate)
    assert 0 <= row["check_seconds"] < 60


def test_contract_and_crash_outcomes():
    facts = ev.points_facts(SQUARE, 2)
    contract = judge(_case(SQUARE), AlgorithmConfig("test-ev-hull"), CallOutcome("contract", error="planted"), facts)
    assert (contract["status"], contract["reason"]) == ("fail", f"{CONTRACT_REASON} planted")
    crash = judge(_case(SQUARE), AlgorithmConfig("test-ev-hull"), CallOutcome("crash", error="SIGSEGV"), facts)
    assert (crash["status"], crash["reason"], crash["stage"]) == ("crash", "SIGSEGV", "algorithm")


@pytest.mark.parametrize("faces, reason", [
    (np.zeros(0, dtype=np.int64), "empty input, empty hull"),
    (np.array([0], dtype=np.int64), "empty input"),
    (FaceSet.from_polygons([]), "empty input, empty hull"),
    (FaceSet.from_polygons([[0, 1, 2]]), "empty input"),
])
def test_no_points_is_a_pass_that_says_whether_the_hull_was_empty(faces, reason):
    facts = _facts(degenerate=True, invalid="no points", rank=None)
    row = judge(_case(np.zeros((0, 2))), AlgorithmConfig("test-ev-hull"), CallOutcome("ok", faces=faces), facts)
    assert (row["status"], row["reason"]) == ("pass", reason)


def test_well_formed_output_on_invalid_input_is_accepted_unchecked():
    nan = np.array([[0.0, np.nan], [1.0, 0.0], [0.0, 1.0]])
    facts = ev.points_facts(nan, 2)
    outcome = CallOutcome("ok", faces=np.array([0, 1, 2]))
    row = judge(_case(nan), AlgorithmConfig("test-ev-hull"), outcome, facts)
    assert row["status"] == "pass"
    assert row["reason"] == ("no hull is defined for invalid input (points contain NaN (1 rows)): "
                             "well-formed output accepted, not checked")


def test_a_correct_and_a_wrong_hull_with_sphere_off():
    ok = evaluate(_case(SQUARE), AlgorithmConfig("test-ev-hull"))
    assert (ok["status"], ok["stage"], ok["reason"], ok["sphere_method"]) == ("pass", "algorithm", "", "")
    bad = evaluate(_case(SQUARE), AlgorithmConfig("test-ev-drops"))
    assert (bad["status"], bad["stage"]) == ("fail", "algorithm")
    assert "containment" in bad["failed_checks"] and bad["reason"]
    assert 0 <= bad["check_seconds"] < 60


def test_a_face_below_three_vertices_on_full_dimensional_3d_input_is_a_contract_failure():
    facts = ev.points_facts(CUBE, 3)
    faces = FaceSet.from_polygons([[0, 1]])
    row = judge(_case(CUBE, 3), AlgorithmConfig("test-ev-hull"), CallOutcome("ok", faces=faces), facts)
    assert (row["status"], row["stage"], row["sphere_method"]) == ("fail", "algorithm", "")
    assert row["reason"].startswith(CONTRACT_REASON)


def test_a_checker_exception_is_an_internal_error_at_the_check_stage(monkeypatch):
    def broken(points, faces, facts):
        raise RuntimeError("planted checker bug")

    monkeypatch.setattr(ev, "_fresh_verdict", broken)
    ev._VERDICTS.clear()
    row = judge(_case(SQUARE), AlgorithmConfig("test-ev-hull"), CallOutcome("ok", faces=np.array([0, 1, 2, 3])),
                ev.points_facts(SQUARE, 2))
    assert (row["status"], row["stage"]) == ("error", "check")
    assert row["reason"] == "internal: checker raised RuntimeError: planted checker bug"
    assert 0 <= row["check_seconds"] < 60


def test_sphere_on_passes_with_the_method_passing_and_keeps_the_causes():
    angles = np.linspace(0, 2 * np.pi, 8, endpoint=False)
    octagon = np.c_[np.cos(angles), np.sin(angles)] * 3.0
    row = evaluate(_case(octagon), AlgorithmConfig("test-ev-hull", "on"))
    assert (row["status"], row["stage"], row["sphere_method"]) == ("pass", "algorithm", "pass")
    assert row["sphere_lost_extreme"] == 0


def test_sphere_on_an_exception_after_a_collapsing_projection_is_the_methods_failure():
    # Two points an eps apart merge in the projection: a full-dimensional triangle becomes a
    # segment, the algorithm then declines it, and the row blames the method.
    facts = ev.points_facts(np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]), 2)
    given = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])  # what the projection left: collinear
    outcome = CallOutcome("raised", error="ValueError: collinear", given=given, index_map=np.array([0, 1, 2]),
                          frame="lib:1 in f")
    case = _case(np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]))
    row = judge(case, AlgorithmConfig("test-ev-hull", "on"), outcome, facts)
    assert (row["status"], row["stage"], row["sphere_method"]) == ("fail", "preprocess", "fail")
    assert row["reason"] == (f"{METHOD_REASON} the projection left a set of affine rank 1 from an input of rank 2: "
                             "its hull cannot map back to the input's hull (the algorithm then raised "
                             "ValueError: collinear)")
    # Sphere off, the same outcome is the algorithm's error on a valid input.
    off = judge(case, AlgorithmConfig("test-ev-hull", "off"), CallOutcome("raised", error="ValueError: x"), facts)
    assert (off["status"], off["stage"]) == ("error", "algorithm")


def test_sphere_on_a_projection_to_invalid_points_is_the_methods_failure():
    case = _case(np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]))
    facts = ev.points_facts(case.points, 2)
    given = np.array([[0.0, 0.0], [np.inf, 0.0], [0.0, 1.0]])
    outcome = CallOutcome("ok", faces=np.array([0, 1, 2]), given=given, index_map=np.array([0, 1, 2]),
                          given_faces=np.array([0, 1, 2]))
    row = judge(case, AlgorithmConfig("test-ev-hull", "on"), outcome, facts)
    assert (row["status"], row["stage"], row["sphere_method"]) == ("fail", "preprocess", "fail")
    assert row["reason"] == f"{METHOD_REASON} the projection left points contain infinity (1 rows) from a valid input"
    # On input that was invalid already, the projection is not to blame.
    assert ev._method_problem(_facts(invalid="x"), _facts(invalid="y")) == ""


def test_sphere_on_offending_point_indices_are_input_rows_and_face_indices_stay():
    import dataclasses

    v = ev._fresh_verdict(SQUARE, np.array([0, 1, 2]), ev.points_facts(SQUARE, 2))
    v = dataclasses.replace(v, offending={"outside": (0, 2), "faces_nonconvex": (1,), "edges_open": (0,)})
    mapped = ev._in_input_rows(v, np.array([7, 8, 9]))
    assert mapped.offending == {"outside": (7, 9), "faces_nonconvex": (1,), "edges_open": (0,)}
    assert v.offending["outside"] == (0, 2)  # a new verdict, the old one unchanged


# --------------------------------------------------------------------------- the verdict cache


def test_the_verdict_cache_never_answers_for_other_facts_or_other_faces():
    ev._VERDICTS.clear()
    facts = ev.points_facts(SQUARE, 2)
    good = ev._verdict(SQUARE, np.array([0, 1, 2, 3]), facts)
    bad = ev._verdict(SQUARE, np.array([0, 1, 2]), facts)
    assert good.ok and not bad.ok
    again = ev._verdict(SQUARE, np.array([0, 1, 2]), facts)
    assert not again.ok and again.offending == bad.offending and again.offending is not bad.offending
    # Other facts object (another case with the same points): computed afresh, same answer.
    assert ev._verdict(SQUARE, np.array([0, 1, 2, 3]), ev.points_facts(SQUARE, 2)).ok
    # A 2D polygon and a FaceSet with the same indices are different outputs.
    assert ev._faces_key(np.array([0, 1, 2])) != ev._faces_key(FaceSet.from_polygons([[0, 1, 2]]))
    assert ev._faces_key(FaceSet.from_polygons([[0, 1, 2]])) != ev._faces_key(FaceSet.from_polygons([[0, 2, 1]]))
    assert ev._faces_key(FaceSet.from_polygons([[0, 1, 2], [0, 2, 3]])) != ev._faces_key(
        FaceSet.from_polygons([[0, 1, 2, 0, 2, 3]]))
    first = next(iter(ev._VERDICTS))
    for k in range(ev._VERDICTS_SIZE + 3):
        moved = SQUARE + k + 1.0
        ev._verdict(moved, np.array([0, 1, 2, 3]), ev.points_facts(moved, 2, qhull=False))
    assert len(ev._VERDICTS) == ev._VERDICTS_SIZE and first not in ev._VERDICTS


def test_fresh_verdicts_route_degenerate_input_to_the_lower_dimensional_judge():
    line = ev.points_facts(LINE, 2)
    assert ev._fresh_verdict(LINE, np.array([0, 2]), line).ok  # the segment's two ends
    assert not ev._fresh_verdict(LINE, np.array([0, 1]), line).ok  # an end missing
    cube = ev.points_facts(CUBE, 3)
    with pytest.raises(ContractViolation):
        ev._fresh_verdict(CUBE, FaceSet.from_polygons([[0, 1]]), cube)
    # Without a reference the Qhull agreement is not judged; with it, it is.
    bare = evaluate(_case(CUBE, 3), AlgorithmConfig("scipy-qhull-3d"), qhull=False)
    assert (bare["status"], bare["qhull_agreement"], bare["qhull_ok"]) == ("pass", None, None)
    with_ref = evaluate(_case(CUBE, 3), AlgorithmConfig("scipy-qhull-3d"))
    assert (with_ref["status"], with_ref["qhull_agreement"], with_ref["qhull_ok"]) == ("pass", "agree", True)
    # A degenerate input's judge gets the reference's simplex and the reference.
    square_in_3d = np.c_[SQUARE, np.zeros(len(SQUARE))]
    flat = ev.points_facts(square_in_3d, 3)
    assert flat.degenerate and flat.affine_rank == 2
    assert evaluate(_case(square_in_3d, 3), AlgorithmConfig("scipy-qhull-3d-QJ"))["status"] in ("pass", "fail")


# --------------------------------------------------------------------------- more of what rows and outcomes carry


@pytest.mark.parametrize("name, sphere, kind", [
    ("test-ev-contract", "off", "contract"), ("test-ev-crash", "off", "crash"), ("test-ev-value", "off", "raised"),
    ("test-ev-out-of-range", "off", "contract"), ("test-ev-out-of-range", "on", "contract"),
    ("test-ev-eps", "off", "ok"), ("test-ev-eps", "on", "ok"), ("test-ev-contract-eps", "off", "contract"),
    ("test-ev-crash-eps", "off", "crash"), ("test-ev-out-of-range-eps", "on", "contract"),
    ("test-ev-hull", "on", "preprocess"),
])
def test_every_outcome_carries_its_time_and_eps(name, sphere, kind):
    takes_eps = name.startswith("test-ev-eps") or name.endswith("-eps")
    points = TINY if kind == "preprocess" else SQUARE
    outcome = call_algorithm(_case(points), AlgorithmConfig(name, sphere, "fixed" if takes_eps else "n/a"))
    assert outcome.kind == kind and 0 < outcome.seconds < 60, outcome
    if takes_eps:
        assert outcome.eps_value == pytest.approx(2.220446049250313e-16)
    if kind == "contract":
        assert outcome.error and "None" not in outcome.error
    if name == "test-ev-out-of-range":
        assert (outcome.given is not None) == (sphere == "on")
    if kind == "raised":
        assert outcome.given is None and outcome.index_map is None  # sphere off: judged on the case's points


def test_contract_and_crash_outcomes_of_real_calls_with_sphere_on_and_off():
    for sphere in ("off", "on"):
        contract = evaluate(_case(SQUARE), AlgorithmConfig("test-ev-contract", sphere))
        assert (contract["status"], contract["stage"]) == ("fail", "algorithm")
        assert contract["reason"] == f"{CONTRACT_REASON} planted: unreadable output"
        crash = evaluate(_case(SQUARE), AlgorithmConfig("test-ev-crash", sphere))
        assert (crash["status"], crash["reason"]) == ("crash", "killed by SIGSEGV (planted)")


def test_a_library_writing_into_its_read_only_input_is_an_error_not_a_silent_change():
    case = _case(SQUARE.copy())
    row = evaluate(case, AlgorithmConfig("test-ev-writes-read-only"))
    assert row["status"] == "error" and "read-only" in row["reason"] and case.points[0, 0] == 0.0


def test_a_clockwise_library_is_turned_to_the_contracts_orientation():
    row = evaluate(_case(SQUARE), AlgorithmConfig("test-ev-clockwise"))
    assert (row["status"], row["reason"]) == ("pass", "")


def test_faces_of_one_or_two_vertices_are_judged_once_the_rank_is_known():
    # One point, repeated, in 3D: the hull is that point; a face of one vertex says so.
    same = _case(np.tile([[1.0, 2.0, 3.0]], (4, 1)), 3)
    register_algorithm("test-ev-point-3d", dim=3)(lambda points: [[0]])
    register_algorithm("test-ev-segment-3d", dim=3)(lambda points: [[0, 2]])
    try:
        assert evaluate(same, AlgorithmConfig("test-ev-point-3d"))["status"] == "pass"
        line = _case(np.array([[0.0, 0.0, 0.0], [1.0, 1.0, 1.0], [2.0, 2.0, 2.0]]), 3)
        assert evaluate(line, AlgorithmConfig("test-ev-segment-3d"))["status"] == "pass"
    finally:
        ALGORITHMS.remove("test-ev-point-3d")
        ALGORITHMS.remove("test-ev-segment-3d")


def test_a_checked_row_has_a_positive_check_time_and_its_verdict_columns():
    bad = evaluate(_case(SQUARE), AlgorithmConfig("test-ev-drops"))
    assert 0 < bad["check_seconds"] < 60
    angles = np.linspace(0, 2 * np.pi, 8, endpoint=False)
    on = evaluate(_case(np.c_[np.cos(angles), np.sin(angles)] * 3.0), AlgorithmConfig("test-ev-hull", "on"))
    assert (on["status"], on["reason"], on["convexity"], on["containment"]) == ("pass", "", True, True)
    assert on["n_hull_vertices"] == 8


def test_sphere_on_a_correct_hull_of_a_collapsed_projection_is_the_methods_failure():
    case = _case(np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]))
    facts = ev.points_facts(case.points, 2)
    given = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])  # collinear: rank 1 from an input of rank 2
    outcome = CallOutcome("ok", faces=np.array([0, 2]), given=given, index_map=np.array([0, 1, 2]),
                          given_faces=np.array([0, 2]))
    row = judge(case, AlgorithmConfig("test-ev-hull", "on"), outcome, facts)
    assert (row["status"], row["stage"], row["sphere_method"]) == ("fail", "preprocess", "fail")
    assert row["reason"] == (f"{METHOD_REASON} the projection left a set of affine rank 1 from an input of rank 2: "
                             "its hull cannot map back to the input's hull")


def test_the_qhull_reference_and_its_options_reach_every_verdict():
    square_in_3d = np.c_[SQUARE, np.zeros(len(SQUARE))]
    flat = evaluate(_case(square_in_3d, 3), AlgorithmConfig("scipy-qhull-3d-QJ"))
    assert flat["qhull_ok"] is not None and flat["qhull_options"]  # the lower-dimensional judge has it too
    default = evaluate(_case(CUBE, 3), AlgorithmConfig("scipy-qhull-3d"))["qhull_options"]
    assert "Qs" not in default.split()
    opts = evaluate(_case(CUBE, 3), AlgorithmConfig("scipy-qhull-3d"), qhull_options="Qs")
    assert "Qs" in opts["qhull_options"].split()
    assert "Qs" in case_facts(_case(CUBE, 3), qhull_options="Qs").reference.options.split()
    assert "Qs" in ev.points_facts(CUBE, 3, qhull_options="Qs").reference.options.split()
