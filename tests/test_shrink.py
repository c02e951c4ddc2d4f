"""Tests for hullstress.triage.shrink: planted failures shrink to their cause, coordinates simplify."""

from __future__ import annotations

import argparse
import shlex
import sys
import textwrap

import numpy as np
import pytest

from hullstress.case import Case
from hullstress.config import AlgorithmConfig
from hullstress.plugins import load_plugin
from hullstress.triage import Signature, fails_same_way, run_config, shrink, signature_of
from hullstress.triage.simplify import mantissa_bits

#: Four points in convex position, with coordinates that need all 53 bits.
PLANTED = np.array([[0.3, 0.1], [2.7, 0.45], [2.2, 3.3], [0.1, 2.9]])

PLUGIN = textwrap.dedent(
    '''
    """Throw-away plug-ins for tests/test_shrink.py: correct hulls except on planted inputs."""
    import numpy as np
    from scipy.spatial import ConvexHull

    from hullstress import register_algorithm

    PLANTED = np.array(%r)


    def _has_planted(points):
        return all(bool(np.all(points == row, axis=1).any()) for row in PLANTED)


    def _hull(points):
        return [int(i) for i in ConvexHull(points).vertices]  # counter-clockwise in 2D


    @register_algorithm("test-shrink-planted-error", dim=2)
    def planted_error(points):
        """Correct, but raises when the planted 4-point configuration is present."""
        if _has_planted(points):
            raise RuntimeError("planted configuration")
        return _hull(points)


    @register_algorithm("test-shrink-planted-drop", dim=2)
    def planted_drop(points):
        """Correct, but drops one hull vertex when the planted configuration is present."""
        hull = _hull(points)
        return hull[1:] if _has_planted(points) else hull


    @register_algorithm("test-shrink-nan-blind", dim=2)
    def nan_blind(points):
        """Skips non-finite rows instead of rejecting the input, and then counts them as one past the end."""
        keep = np.flatnonzero(np.isfinite(points).all(axis=1))
        hull = [int(keep[i]) for i in ConvexHull(points[keep]).vertices]
        return hull + [len(points)] if len(keep) < len(points) else hull


    @register_algorithm("test-shrink-left", dim=2)
    def left(points):
        """Correct, but raises when some point has x < -0.5."""
        if float(points[:, 0].min()) < -0.5:
            raise ValueError("a point left of -0.5")
        return _hull(points)
    '''
    % (PLANTED.tolist(),)
)


@pytest.fixture(scope="module", autouse=True)
def plugin(tmp_path_factory):
    path = tmp_path_factory.mktemp("shrink-plugin") / "shrink_plugins.py"
    path.write_text(PLUGIN)
    load_plugin(str(path))
    return path


def _hidden_case(n: int = 500, seed: int = 7) -> Case:
    rng = np.random.default_rng(seed)
    cloud = rng.uniform(-10, 10, size=(n - len(PLANTED), 2))
    pts = np.vstack([cloud, PLANTED])
    pts = pts[rng.permutation(n)]  # scatter the planted rows
    return Case(points=pts, dim=2, family="test-planted", params={"n": n}, seed=seed, size=n)


def _rows(points: np.ndarray) -> set[tuple[float, ...]]:
    return {tuple(map(float, p)) for p in points}


@pytest.mark.parametrize("algorithm, check", [("test-shrink-planted-error", "error"),
                                              ("test-shrink-planted-drop", "containment")])
def test_planted_four_points_hidden_in_500_shrink_to_at_most_6(algorithm, check):
    case = _hidden_case()
    config = AlgorithmConfig(algorithm)
    row = run_config(case, config, timeout=30)
    sig = signature_of(row)
    assert sig is not None and sig.check == check, (row.status, row.get("reason"))
    result = shrink(case, config, sig, timeout=30)
    assert result.reproduced and not result.exhausted, result.note
    assert result.original_size == 500
    assert result.minimal_size <= 6
    # The failure needs exactly the planted rows, with their exact coordinates.
    assert _rows(PLANTED) <= _rows(result.case.points), (result.steps, result.case.points.tolist(), result.row.get("reason"))
    assert fails_same_way(result.case, config, sig)
    assert result.row is not None and signature_of(result.row).check == check
    assert result.case.params["shrunk_from"] == case.case_id and result.case.family == case.family


def test_coordinates_are_simplified_when_the_failure_survives():
    rng = np.random.default_rng(3)
    pts = rng.uniform(-10, 10, size=(60, 2))
    case = Case(points=pts, dim=2, family="test-left", seed=3, size=60)
    config = AlgorithmConfig("test-shrink-left")
    assert int(mantissa_bits(pts).max()) > 40
    result = shrink(case, config, timeout=30)
    assert result.reproduced and result.signature.check == "error"
    assert result.minimal_size == 3  # fewer points is degenerate, hence rejected, not an error
    assert result.max_mantissa_bits <= 4, result.case.points.tolist()
    assert result.case.points[:, 0].min() < -0.5
    assert any("bits" in s or "replaced" in s for s in result.steps)
    assert fails_same_way(result.case, config, result.signature)


@pytest.mark.parametrize("cap", [0, 3, 8])
def test_simplifying_stops_at_its_own_budget_with_a_case_that_still_fails(cap):
    # TriageBudget.simplify_calls: deleting points is not limited by it, simplifying is.
    rng = np.random.default_rng(3)
    case = Case(points=rng.uniform(-10, 10, size=(60, 2)), dim=2, family="test-left", seed=3, size=60)
    config = AlgorithmConfig("test-shrink-left")
    plain = shrink(case, config, timeout=30, simplify=False)
    capped = shrink(case, config, timeout=30, simplify_calls=cap)
    full = shrink(case, config, timeout=30)
    assert full.calls > plain.calls + 8  # the uncapped passes need more than any cap tried here
    assert (plain.calls < capped.calls <= plain.calls + cap) if cap else capped.calls == plain.calls
    assert f"coordinates simplified within {cap} evaluations" in capped.steps
    assert capped.minimal_size == plain.minimal_size == 3 and not capped.exhausted, capped.note
    assert capped.verified and fails_same_way(capped.case, config, capped.signature)
    if cap:  # the first simplifying steps (scale, fewest bits for all) are the ones kept
        assert int(mantissa_bits(capped.case.points).max()) < int(mantissa_bits(plain.case.points).max())


def test_evaluation_budget_stops_early_with_a_case_that_still_fails():
    case = _hidden_case(n=200, seed=1)
    config = AlgorithmConfig("test-shrink-planted-error")
    sig = signature_of(run_config(case, config, timeout=30))
    assert sig.status == "error" and sig.error == "RuntimeError" and sig.frame.endswith(" in planted_error")
    result = shrink(case, config, sig, max_calls=4, timeout=30)
    assert result.exhausted and result.calls <= 4
    assert "evaluation budget (4) spent while deleting points" in result.note
    assert result.minimal_size <= 200
    assert fails_same_way(result.case, config, sig)


def test_a_case_that_does_not_fail_is_returned_unshrunk():
    case = Case.from_points([[0, 0], [1, 0], [0, 1], [1, 1], [0.5, 0.5]], family="test-clean")
    config = AlgorithmConfig("test-shrink-planted-error")
    result = shrink(case, config)
    assert not result.reproduced and "does not fail" in result.note and result.case is case
    sig = Signature(config.algorithm, "off", "n/a", status="error", error="RuntimeError")
    again = shrink(case, config, sig)
    assert not again.reproduced and "did not reproduce" in again.note and again.calls == 1


def test_timeout_signature_without_isolation_is_not_run_in_process(monkeypatch):
    import hullstress.runner as runner

    monkeypatch.delattr(runner, "run_one", raising=False)
    case = _hidden_case(n=20)
    config = AlgorithmConfig("test-shrink-planted-error")
    result = shrink(case, config, Signature(config.algorithm, "off", "n/a", status="timeout"))
    assert not result.reproduced and "run_one" in result.note and result.calls == 0


# --------------------------------------------------------------------------- the shrink subcommand


def _cli(argv: list[str]) -> int:
    from hullstress.cli import _shrink

    parser = argparse.ArgumentParser(prog="hullstress")
    _shrink.add_parser(parser.add_subparsers())
    args = parser.parse_args(argv)
    return args.handler(args)


def test_shrink_command_writes_the_minimal_case_and_exits_1(plugin, tmp_path, capsys):
    from hullstress.io import write_points

    src = write_points(tmp_path / "case.csv", _hidden_case(n=80).points)
    out = tmp_path / "out"
    code = _cli(["shrink", str(src), "--algorithm", "test-shrink-planted-error", "--plugin", str(plugin),
                 "--budget", "30", "--out", str(out)])
    assert code == 1
    printed = capsys.readouterr().out
    assert "shrunk 80 -> 4 points" in printed
    (folder,) = list((next(out.iterdir()) / "failures").iterdir())
    assert _rows(np.load(folder / "points.npy")) == _rows(PLANTED)
    assert (folder / "reproduce.txt").read_text().strip() in printed


def test_shrink_command_exits_0_when_the_case_does_not_fail(plugin, tmp_path, capsys):
    from hullstress.io import write_points

    src = write_points(tmp_path / "clean.csv", np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]))
    assert _cli(["shrink", str(src), "--algorithm", "test-shrink-planted-error", "--out", str(tmp_path)]) == 0
    assert "does not reproduce" in capsys.readouterr().out
    # A failure other than the one asked for does not count either.
    src = write_points(tmp_path / "bad.csv", _hidden_case(n=20).points)
    assert _cli(["shrink", str(src), "--algorithm", "test-shrink-planted-error", "--check", "containment",
                 "--no-shrink"]) == 0
    assert _cli(["shrink", str(src), "--algorithm", "test-shrink-planted-error", "--check", "error",
                 "--no-shrink"]) == 1


def test_invalid_input_failures_reproduce_through_the_raw_npy_command(plugin, tmp_path):
    from hullstress.report.failures import write_failure_folder
    from hullstress.triage.stage import triage_one

    pts = np.vstack([_hidden_case(n=30).points, [[np.nan, 1.0]]])
    case = Case(points=pts, dim=2, family="test-nan", seed=0)
    config = AlgorithmConfig("test-shrink-nan-blind")
    result = shrink(case, config, timeout=30)
    # A hull for non-finite input is accepted unchecked (docs/lower-dimensional.md); an index out of range is not.
    assert result.signature.check == "contract"
    assert result.minimal_size == 4 and np.isnan(result.case.points).any()  # 3 finite points make a hull
    rec = write_failure_folder(tmp_path / "failures", triage_one(result, config), plugins=[str(plugin)], picture=True)
    assert not (rec.folder / "points.csv").exists()  # the reader refuses NaN: only the .npy is exact
    assert rec.verified is True
    argv = shlex.split(rec.command)
    assert argv[:4] == [sys.executable, "-m", "hullstress", "reproduce"]
    from hullstress.cli import main

    assert main(argv[3:]) == 1


# --------------------------------------------------------------------------- in-house algorithms

CLAIM_FAMILIES = ("kettner-classroom", "kettner-ulp-grid", "coplanar-grid")


def _in_house_groups():
    from hullstress._registry import algorithms, generators
    from hullstress.sweep import SweepOptions, run_sweep
    from hullstress.triage import group_failures

    names = tuple(s.name for s in algorithms() if s.origin == "in-house")
    families = tuple(f for f in CLAIM_FAMILIES if f in {g.name for g in generators()})
    if not names or not families:
        pytest.skip(f"in-house algorithms {names or 'none'} / families {families or 'none'} not registered yet")
    result = run_sweep(SweepOptions(profile="quick", algorithms=names, generators=families, workers=2))
    cases = {c.case_id: c for c in result.cases}
    # Hangs cost a full timeout per call: the timeout groups are not shrunk here.
    groups = [g for g in group_failures(result.table) if g.signature.status != "timeout"]
    return groups, cases


def _shrinks_less(signature) -> str | None:
    """Why a group may keep more than 10 points (docs/triage.md), or None."""
    if signature.sphere == "on":
        return "sphere on: the projection's centre and scale depend on every point, so a deletion moves the rest"
    if signature.error == "AlgorithmStepLimit":
        return "a step limit that grows with n: whether it trips depends on how many points are left"
    return None


def _assert_shrinks_to_10(groups, cases, budget):
    too_big, sizes = [], []
    for g in groups:
        res = shrink(cases[g.smallest_case_id], g.signature.config, g.signature, max_calls=budget, timeout=10)
        assert res.reproduced, (g.signature.label, res.note)
        assert fails_same_way(res.case, g.signature.config, g.signature, timeout=10)
        assert res.minimal_size <= res.original_size
        sizes.append(res.minimal_size)
        if res.minimal_size > 10 and _shrinks_less(g.signature) is None:
            too_big.append((g.signature.label, res.original_size, res.minimal_size, res.exhausted))
    assert not too_big, too_big
    assert sorted(sizes)[len(sizes) // 2] <= 10  # the median, whatever the exceptions


def test_in_house_kettner_and_coplanar_failures_shrink_to_10_points_one_per_family():
    groups, cases = _in_house_groups()
    first: dict[str, object] = {}
    for g in groups:
        first.setdefault(g.family_names[0], g)
    if not first:
        pytest.skip("the in-house algorithms did not fail on the Kettner and coplanar-grid families this run")
    _assert_shrinks_to_10(list(first.values()), cases, budget=300)


@pytest.mark.slow
def test_in_house_kettner_and_coplanar_failures_shrink_to_10_points_every_group():
    groups, cases = _in_house_groups()
    if not groups:
        pytest.skip("the in-house algorithms did not fail on the Kettner and coplanar-grid families this run")
    _assert_shrinks_to_10(groups, cases, budget=600)


# --------------------------------------------------------------------------- the state machine, with made-up rows


def _drive(shrinker, answer):
    """Answer every question of a Shrinker with ``answer(points, with_reference)``; return the questions asked."""
    asked = []
    question = shrinker.ask()
    while question is not None:
        asked.append(question)
        question = shrinker.answer(answer(*question))
    return asked


def test_steps_kept_without_the_reference_that_fail_with_it_are_undone():
    from hullstress.results import ResultRow
    from hullstress.triage import Shrinker

    planted = {0, 5, 9, 13}
    sig = Signature("made-up", "off", "n/a", checks="containment,qhull_agreement", severity="gross")
    base = {"algorithm": "made-up", "sphere": "off", "eps": "n/a", "reason": ""}

    def answer(points, with_reference):
        ids = {int(p[0]) for p in points}
        if not planted <= ids:
            return ResultRow({**base, "status": "pass", "failed_checks": ""})
        if not with_reference:  # nothing fails qhull_agreement without the reference
            return ResultRow({**base, "status": "fail", "failed_checks": "containment", "severity": "roundoff"})
        # With the reference the violation is gross only while at least 6 points are left.
        severity = "gross" if len(ids) >= 6 else "roundoff"
        return ResultRow({**base, "status": "fail", "failed_checks": "containment,qhull_agreement",
                          "severity": severity})

    case = Case.from_points(np.column_stack([np.arange(16.0), np.zeros(16)]), family="made-up")
    sweep_row = answer(case.points, True)
    shrinker = Shrinker(case, sig, max_calls=500, row=sweep_row, simplify=False)
    asked = _drive(shrinker, answer)
    result = shrinker.result()
    assert any(not ref for _, ref in asked) and any(ref for _, ref in asked)  # cheap first, exact when it counts
    assert result.reproduced and result.verified is True
    assert result.minimal_size == 6 and planted <= {int(p[0]) for p in result.case.points}
    assert signature_of(result.row) == sig  # the row in the folder is exact
    assert any("did not hold with it" in step for step in result.steps)
    # The same questions in the same order on a second run: the shrink depends on the answers alone.
    again = Shrinker(case, sig, max_calls=500, row=sweep_row, simplify=False)
    assert [(p.tobytes(), r) for p, r in _drive(again, answer)] == [(p.tobytes(), r) for p, r in asked]


def test_an_interrupted_shrink_without_the_reference_keeps_the_sweep_case():
    from hullstress.results import ResultRow
    from hullstress.triage import Shrinker

    sig = Signature("made-up", "off", "n/a", checks="containment,qhull_agreement", severity="gross")
    row = ResultRow({"algorithm": "made-up", "sphere": "off", "eps": "n/a", "reason": "", "status": "fail",
                     "failed_checks": "containment", "severity": "gross"})
    case = Case.from_points(np.column_stack([np.arange(8.0), np.zeros(8)]), family="made-up")
    shrinker = Shrinker(case, sig, max_calls=50)
    shrinker.ask()
    for _ in range(3):
        shrinker.answer(row)
    result = shrinker.stop("interrupted")
    assert not result.reproduced and result.case is case and result.note == "interrupted"


def test_only_the_confirmation_of_the_minimal_case_is_marked_as_a_rerun():
    """A cache of earlier calls may answer any question but the deliberate re-run (it shows flaky failures)."""
    from hullstress.results import ResultRow
    from hullstress.triage import Shrinker

    planted = {2, 5}
    base = {"algorithm": "made-up", "sphere": "off", "eps": "n/a"}
    error = ResultRow({**base, "status": "error", "stage": "algorithm", "reason": "ValueError: planted",
                       "error_frame": "m:3 in f"})
    sig = signature_of(error)

    def answer(points):
        return error if planted <= {int(p[0]) for p in points} else ResultRow({**base, "status": "pass"})

    case = Case.from_points(np.column_stack([np.arange(8.0), np.zeros(8)]), family="made-up")
    shrinker = Shrinker(case, sig, max_calls=200, simplify=False)
    marks = []
    question = shrinker.ask()
    while question is not None:
        marks.append((question[0].copy(), shrinker.rerun))
        question = shrinker.answer(answer(question[0]))
    assert not shrinker.rerun  # nothing pending
    reruns = [points for points, rerun in marks if rerun]
    assert len(reruns) == 1 and marks[-1][1]
    assert np.array_equal(reruns[0], shrinker.result().case.points)
    assert {int(p[0]) for p in reruns[0]} == planted
