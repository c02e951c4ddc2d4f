"""One verdict per distinct output of a case: configs that return the same hull are judged once.

The verdict is a function of the points, the canonical faces and the case
facts; the cache must give the row a fresh judgement would give, and must not
serve a verdict computed with other facts or other points.
"""

from __future__ import annotations

import numpy as np
import pytest

import hullstress.evaluate as evaluate_module
from hullstress import AlgorithmConfig, Case
from hullstress.evaluate import call_algorithm, case_facts, judge
from hullstress.results import TIMING_COLUMNS


@pytest.fixture
def counted(monkeypatch):
    """Count the verdicts actually computed (not served from the cache); start with an empty cache."""
    calls = []
    fresh = evaluate_module._fresh_verdict

    def counting(points, faces, facts):
        calls.append(len(points))
        return fresh(points, faces, facts)

    monkeypatch.setattr(evaluate_module, "_fresh_verdict", counting)
    monkeypatch.setattr(evaluate_module, "_VERDICTS", type(evaluate_module._VERDICTS)())
    return calls


def _row_values(row):
    return {k: v for k, v in row.values.items() if k not in TIMING_COLUMNS and k not in ("eps", "config", "eps_value")}


def _cloud(seed: int = 3, n: int = 30) -> Case:
    return Case.from_points(np.random.default_rng(seed).random((n, 2)), family="test-random", seed=seed)


def test_the_same_output_twice_is_judged_once_with_the_same_row(counted):
    case = _cloud()
    facts = case_facts(case)
    # Both eps policies give monotone chain the same hull on a random cloud.
    rows = [judge(case, c, call_algorithm(case, c), facts)
            for c in (AlgorithmConfig("monotone-chain", eps="scaled"), AlgorithmConfig("monotone-chain", eps="fixed"))]
    assert len(counted) == 1
    assert rows[0].status == rows[1].status == "pass"
    assert _row_values(rows[0]) == _row_values(rows[1])


def test_a_wrong_output_served_from_the_cache_keeps_its_findings(counted):
    case = _cloud(seed=5)
    facts = case_facts(case)
    poly = call_algorithm(case, AlgorithmConfig("monotone-chain", eps="scaled")).faces
    cut = np.delete(poly, 1)  # one corner cut off
    first = evaluate_module._verdict(case.points, cut, facts)
    first.offending.clear()  # a caller scribbling on its verdict must not reach the cached one
    second = evaluate_module._verdict(case.points, cut, facts)
    assert len(counted) == 1
    assert not second.ok and "containment" in second.offending
    assert second.failed_checks == first.failed_checks


def test_other_facts_or_other_points_are_judged_afresh(counted):
    case = _cloud(seed=7)
    faces = call_algorithm(case, AlgorithmConfig("monotone-chain", eps="scaled")).faces
    evaluate_module._verdict(case.points, faces, case_facts(case))
    evaluate_module._verdict(case.points, faces, case_facts(case, qhull=False))  # other facts object
    moved = case.points.copy()
    moved[0] += 0.5  # same faces, other coordinates
    evaluate_module._verdict(moved, faces, case_facts(Case.from_points(moved)))
    assert len(counted) == 3
