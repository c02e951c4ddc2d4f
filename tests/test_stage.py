"""Stage attribution: every row says whether preprocessing, the algorithm or the checker produced its verdict."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from hullstress import get_generator
from hullstress.case import Case
from hullstress.config import AlgorithmConfig
from hullstress.triage.signature import is_failure_verdict, verdict_of
from hullstress.evaluate import evaluate
from hullstress.records import Stage
from hullstress.report.tables import failure_counts, status_counts
from hullstress.results import to_frame
from hullstress.triage import signature_of
from hullstress._registry import ALGORITHMS, register_algorithm

from _hull_oracle import qhull_outward


def _qhull_3d(points):
    """Qhull through scipy, every triangle turned outward (a test algorithm, correct on random clouds)."""
    return qhull_outward(points)


def _raises(points):
    """Always raises (a test algorithm)."""
    raise ZeroDivisionError("boom")


@pytest.fixture(scope="module", autouse=True)
def test_algorithms():
    """Registered for this module only: other modules (the corpus replay) run every registered algorithm."""
    register_algorithm("test-qhull-3d-stage", dim=3)(_qhull_3d)
    register_algorithm("test-raises-2d", dim=2)(_raises)
    yield
    ALGORITHMS.remove("test-qhull-3d-stage")
    ALGORITHMS.remove("test-raises-2d")


def _ball(n: int = 24, seed: int = 0) -> Case:
    rng = np.random.default_rng(seed)
    pts = rng.normal(size=(n, 3))
    return Case(points=pts, dim=3, family="uniform", params={"seed": seed}, seed=seed, size=n)


def test_sphere_method_failure_is_preprocess_not_the_algorithm():
    # On a random cloud the support mapping drops hull vertices (sphere.py, "Known weakness"):
    # the algorithm's hull of the projected points is right, mapped back it is not the input's hull.
    case = _ball()
    row = evaluate(case, AlgorithmConfig("test-qhull-3d-stage", "on"))
    assert (row["status"], row["stage"], row["sphere_method"]) == ("fail", "preprocess", "fail")
    assert row["reason"].startswith("sphere method: mapped back, the algorithm's correct hull of the")
    assert "containment" in row["failed_checks"]
    off = evaluate(case, AlgorithmConfig("test-qhull-3d-stage", "off"))
    assert (off["status"], off["stage"], off["sphere_method"]) == ("pass", "algorithm", "")


def test_sphere_on_judges_the_algorithm_on_the_projected_points():
    # Every point of a regular polygon is extreme and the farthest along its own direction:
    # the method keeps the hull, so a correct algorithm passes with the method passing too.
    angles = np.linspace(0, 2 * np.pi, 12, endpoint=False)
    case = Case(points=np.c_[np.cos(angles), np.sin(angles)] * 3.0, dim=2, family="regular-polygon")
    row = evaluate(case, AlgorithmConfig("monotone-chain", "on", "scaled"))
    assert (row["status"], row["stage"], row["sphere_method"]) == ("pass", "algorithm", "pass")


def test_a_preprocessing_exception_is_never_the_algorithms_error():
    # Coordinates ~1e-170: the squares in the projection underflow, so a surface point has no
    # direction; the sphere method raises on a valid, full-dimensional input.
    case = Case(points=_ball().points * 1e-170, dim=3, family="scaled")
    row = evaluate(case, AlgorithmConfig("test-qhull-3d-stage", "on"))
    assert (row["status"], row["stage"], row["sphere_method"]) == ("error", "preprocess", "error")
    assert row["reason"].startswith("preprocess: sphere projection: ValueError")
    # The same method on invalid input declines it: rejected, still at preprocess.
    nan = Case(points=np.where(np.eye(24, 3, dtype=bool), np.nan, _ball().points), dim=3, family="bad-input")
    row = evaluate(nan, AlgorithmConfig("test-qhull-3d-stage", "on"))
    assert (row["status"], row["stage"]) == ("rejected", "preprocess")


def test_a_checker_exception_is_stage_check(monkeypatch):
    import hullstress.checker

    def broken(*args, **kwargs):
        raise RuntimeError("checker bug")

    monkeypatch.setattr(hullstress.checker, "check", broken)
    row = evaluate(_ball(), AlgorithmConfig("test-qhull-3d-stage", "off"))
    assert (row["status"], row["stage"]) == ("error", "check")
    assert row["reason"] == "internal: checker raised RuntimeError: checker bug"


def test_the_algorithms_own_exception_stays_the_algorithms():
    case = Case(points=np.random.default_rng(1).random((10, 2)), dim=2, family="uniform")
    row = evaluate(case, AlgorithmConfig("test-raises-2d"))
    assert (row["status"], row["stage"], row["reason"]) == ("error", "algorithm", "ZeroDivisionError: boom")


@pytest.mark.parametrize("scale", [1e300, 1.7976931348623157e308])
def test_extreme_scale_eps_is_finite_and_never_the_algorithms_error(scale):
    """Issue 13 item 4: above ~1e154 the scaled eps overflowed and the projection raised as the algorithm's error."""
    spec = get_generator("scaled")
    pts = spec.func(np.random.default_rng(0), 24, dim=3, scale=scale)
    case = Case(points=pts, dim=3, family="scaled", params={"scale": scale})
    for config in (AlgorithmConfig("kenwright", "off", "scaled"), AlgorithmConfig("kenwright", "on", "scaled"),
                   AlgorithmConfig("test-qhull-3d-stage", "on")):
        row = evaluate(case, config)
        assert "eps must be" not in row["reason"], (config.label, row["reason"])
        if config.sphere == "off":
            assert np.isfinite(row["eps_value"]) and row["eps_value"] > 0
        else:
            # The method collapses or overflows at this scale: its failure, never the algorithm's.
            assert (row["status"], row["stage"]) in (("fail", "preprocess"), ("error", "preprocess")), row["reason"]
            assert row["eps_value"] is None or np.isfinite(row["eps_value"])
            if row["status"] == "fail" and not row["failed_checks"]:
                sig = signature_of(row)  # the projection collapsed the cloud: no hull to check
                assert (sig.check, sig.stage) == ("collapsed", "preprocess")


def test_counts_signatures_and_corpus_keep_the_stages_apart():
    case = _ball()
    rows = [evaluate(case, AlgorithmConfig("test-qhull-3d-stage", s)) for s in ("off", "on")]
    table = to_frame(rows)
    counts = status_counts(table, ["algorithm"]).iloc[0]
    assert (counts["failed"], counts["method_failed"], counts["internal_errors"], counts["fail"]) == (0, 1, 0, 1)
    assert counts["failure_rate"] == 0.0
    assert failure_counts(table)[["sphere", "failed", "method_failed"]].values.tolist() == [["on", 0, 1]]
    sig = signature_of(rows[1])
    assert sig.stage == "preprocess" and "__preprocess__" in sig.slug and "in preprocess" in sig.label
    assert verdict_of(rows[1]).startswith("fail in preprocess containment")
    assert is_failure_verdict(verdict_of(rows[1]))
    # A table from before the stage column reads as the algorithm's.
    old = table.drop(columns=["stage"])
    assert signature_of(old.iloc[1].to_dict()).stage == Stage.ALGORITHM
    assert status_counts(old, ["algorithm"]).iloc[0]["failed"] == 1


def test_stage_values_and_table_dtypes():
    rows = [evaluate(_ball(), AlgorithmConfig("test-qhull-3d-stage", "on"))]
    table = to_frame(rows)
    assert table["stage"].dtype == pd.StringDtype() and set(table["stage"]) <= {s.value for s in Stage}
