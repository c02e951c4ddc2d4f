"""Tests for hullstress.triage: signatures, grouping, ddmin, coordinate simplification, the oracle."""

from __future__ import annotations

import re
from fractions import Fraction

import numpy as np
import pandas as pd
import pytest
from hypothesis import example, given
from hypothesis import strategies as st

from hullstress.case import Case
from hullstress.config import AlgorithmConfig
from hullstress.results import ResultRow
from hullstress.triage import IsolationUnavailable, Signature, failed_check, group_failures, groups_frame, signature_of
from hullstress.triage import oracle
from hullstress.triage.ddmin import ddmin
from hullstress.triage.simplify import coordinate_candidates, mantissa_bits, pow2_normalize, round_mantissa

# --------------------------------------------------------------------------- signatures

FAILED_CHECK_CASES = [
    # status, reason, failed_checks, expected
    ("pass", "", "", None),
    ("rejected", "ValueError: coplanar", "", None),
    ("fail", "", "containment", "containment"),
    ("fail", "", "qhull_agreement,convexity", "convexity"),  # report order, not cell order
    ("fail", "output contract: index 9 out of range", "", "contract"),
    ("fail", "returned a hull for invalid input (points contain NaN)", "", "invalid-input"),
    ("error", "ZeroDivisionError: division by zero", "", "error"),
    ("timeout", "no result after 10 s", "", "timeout"),
    ("crash", "signal 11", "", "crash"),
    ("fail", float("nan"), pd.NA, "invalid-input"),
]


@pytest.mark.parametrize("status, reason, checks, expected", FAILED_CHECK_CASES)
def test_failed_check(status, reason, checks, expected):
    assert failed_check(status, reason, checks) == expected


@pytest.mark.parametrize(
    "names",
    [
        ("gift-wrap", "family"),
        ("my/alg", "coplanar grid"),
        ("..", "../../etc"),
        ("alg:1", "fam*?"),
        ("x" * 300, "y"),
    ],
)
def test_slug_is_filesystem_safe(names):
    alg, fam = names
    slug = Signature(alg, "on", "fixed", "containment", fam).slug
    assert re.fullmatch(r"[A-Za-z0-9._-]+", slug), slug
    assert slug not in (".", "..") and not slug.startswith(".")
    assert len(slug) <= 160


def test_slugs_of_distinct_signatures_differ_even_after_sanitising():
    a = Signature("my/alg", "on", "fixed", "containment", "fam")
    b = Signature("my-alg", "on", "fixed", "containment", "fam")
    c = Signature("my alg", "on", "fixed", "containment", "fam")
    assert len({a.slug, b.slug, c.slug}) == 3


def test_signature_of_a_result_row_and_config():
    row = ResultRow({"algorithm": "alg", "sphere": "on", "eps": "fixed", "generator": "coplanar-grid",
                     "status": "fail", "reason": "containment: 2 points outside", "failed_checks": "containment"})
    sig = signature_of(row)
    assert sig == Signature("alg", "on", "fixed", "containment", "coplanar-grid")
    assert sig.config == AlgorithmConfig("alg", "on", "fixed")
    assert sig.status == "fail"
    assert Signature("alg", "off", "n/a", "crash", "f").status == "crash"


# --------------------------------------------------------------------------- grouping


def _table(rows):
    base = {"algorithm": "alg", "sphere": "off", "eps": "n/a", "generator": "fam", "reason": "",
            "failed_checks": "", "n_points": 10}
    return pd.DataFrame([{**base, **r} for r in rows])


def test_group_failures_counts_smallest_and_representative():
    table = _table([
        {"case_id": "c1", "status": "fail", "failed_checks": "containment", "n_points": 50},
        {"case_id": "c2", "status": "fail", "failed_checks": "containment,qhull_agreement", "n_points": 8},
        {"case_id": "c3", "status": "fail", "failed_checks": "containment", "n_points": 8},
        {"case_id": "c4", "status": "pass"},
        {"case_id": "c5", "status": "rejected", "reason": "ValueError"},
        {"case_id": "c6", "status": "error", "reason": "KeyError: 3"},
        {"case_id": "c1", "status": "fail", "sphere": "on", "failed_checks": "convexity"},
        {"case_id": "c7", "status": "error", "generator": "other", "reason": "KeyError: 4", "n_points": 3},
    ])
    groups = group_failures(table)
    by = {(g.signature.sphere, g.signature.check, g.signature.family): g for g in groups}
    assert set(by) == {("off", "containment", "fam"), ("off", "error", "fam"), ("on", "convexity", "fam"),
                       ("off", "error", "other")}
    cont = by[("off", "containment", "fam")]
    assert (cont.count, cont.cases) == (3, 3)
    assert cont.smallest_case_id == "c2" and cont.smallest_n_points == 8  # first of the two smallest
    assert cont.representative_case_id == "c1"
    assert cont.smallest_index == 1
    # Denominator: every call of alg[sphere=off] on fam (c1..c6 at sphere off).
    assert cont.calls == 6
    assert by[("on", "convexity", "fam")].calls == 1
    assert groups[0] is cont  # most frequent first
    frame = groups_frame(groups)
    assert list(frame["failures"]) == [g.count for g in groups]
    assert frame.loc[0, "rate"] == pytest.approx(3 / 6, abs=1e-3)


def test_group_failures_of_a_clean_or_empty_table():
    assert group_failures(_table([{"case_id": "a", "status": "pass"}, {"case_id": "b", "status": "rejected"}])) == []
    assert group_failures(_table([]).iloc[0:0]) == []


# --------------------------------------------------------------------------- ddmin


@given(n=st.integers(2, 200), data=st.data())
def test_ddmin_finds_exactly_the_planted_rows(n, data):
    planted = data.draw(st.sets(st.integers(0, n - 1), min_size=1, max_size=min(n, 6)))
    calls = []

    def fails(subset):
        calls.append(subset)
        return planted <= set(subset)

    assert set(ddmin(n, fails)) == planted
    assert len(calls) < 40 * len(planted) * max(1, int(np.log2(n)) + 1)


def test_ddmin_result_is_one_minimal_for_a_non_monotone_predicate():
    # Fails when the subset has an odd number of rows >= 3 including row 0 (not monotone).
    def fails(s):
        return 0 in s and len(s) >= 3 and len(s) % 2 == 1

    keep = ddmin(9, fails)
    assert fails(keep)
    assert all(not fails(tuple(i for i in keep if i != j)) for j in keep)


def test_ddmin_respects_min_size_and_propagates_a_stop():
    assert ddmin(10, lambda s: True, min_size=4) == (0, 1, 2, 3) or len(ddmin(10, lambda s: True, min_size=4)) == 4

    class Stop(Exception):
        pass

    def stopper(s):
        raise Stop()

    with pytest.raises(Stop):
        ddmin(10, stopper)


# --------------------------------------------------------------------------- coordinate simplification


finite = st.floats(allow_nan=False, allow_infinity=False)


@given(x=finite, bits=st.integers(1, 53))
def test_round_mantissa_keeps_at_most_bits_and_is_nearest(x, bits):
    r = float(round_mantissa(np.array([x]), bits)[0])
    if x == 0:
        assert r == 0
        return
    assert np.isfinite(r)
    assert mantissa_bits(np.array([r]))[0] <= bits
    assert np.sign(r) == np.sign(x) or r == 0
    # Relative error at most half a unit in the last kept place (a whole unit where
    # rounding up would overflow and the value is truncated instead).
    slack = 2.0 ** (1 - bits) if abs(x) >= 2.0**1023 else 2.0 ** (-bits)
    assert abs(r - x) <= abs(x) * slack * 1.0000001 + 5e-324


@given(x=finite)
def test_round_mantissa_53_bits_is_identity(x):
    assert float(round_mantissa(np.array([x]), 53)[0]) == x


def test_round_mantissa_leaves_non_finite_alone():
    out = round_mantissa(np.array([np.nan, np.inf, -np.inf, 0.3]), 1)
    assert np.isnan(out[0]) and out[1] == np.inf and out[2] == -np.inf and out[3] == 0.25
    with pytest.raises(ValueError, match="bits must be in 1..53, got 0"):
        round_mantissa(np.array([1.0]), 0)


@given(st.lists(st.floats(min_value=-1e300, max_value=1e300, allow_nan=False), min_size=1, max_size=12))
# Found by the random profile: a lone subnormal is scaled up by 2**1026, a ratio that a
# float division overflows (the scaling itself is exact; the old float check was wrong).
@example(values=[2.225073858507203e-309])
@example(values=[5e-324, -0.0])
def test_pow2_normalize_is_exact_and_lands_in_1_2(values):
    pts = np.array(values).reshape(-1, 1)
    out = pow2_normalize(pts)
    if out is None:
        return
    m = np.max(np.abs(out))
    assert 1.0 <= m < 2.0
    # Exactness in rationals: one power-of-two factor for every value (zeros stay zero).
    ratios = {Fraction(float(o)) / Fraction(float(p)) for o, p in zip(out.ravel(), pts.ravel()) if p != 0}
    assert len(ratios) == 1
    (ratio,) = ratios
    power = ratio.numerator * ratio.denominator  # 2**|k| when the ratio is 2**k
    assert ratio > 0 and 1 in (ratio.numerator, ratio.denominator) and power & (power - 1) == 0
    assert np.all((out == 0) == (pts == 0))


def test_coordinate_candidates_are_simpler():
    for x in (0.1, -123.456, 1e-300, 7.0):
        bits = mantissa_bits(np.array([x]))[0]
        cands = coordinate_candidates(x)
        assert cands[0] == 0.0
        assert all(c != x for c in cands)
        assert all(mantissa_bits(np.array([c]))[0] < bits for c in cands)


# --------------------------------------------------------------------------- oracle


def test_run_config_prefers_the_isolated_runner(monkeypatch):
    import hullstress.runner as runner

    seen = []

    def fake_run_one(case, config, *, timeout, facts=None):
        seen.append((case.n_points, config.label, timeout))
        return ResultRow({"algorithm": config.algorithm, "sphere": config.sphere, "eps": config.eps,
                          "generator": case.family, "status": "crash", "reason": "signal 11", "failed_checks": ""})

    monkeypatch.setattr(runner, "run_one", fake_run_one, raising=False)
    case = Case.from_points([[0, 0], [1, 0], [0, 1]])
    config = AlgorithmConfig("anything")
    assert oracle.fails_same_way(case, config, Signature("anything", "off", "n/a", "crash", "x"), timeout=2.5)
    assert not oracle.fails_same_way(case, config, Signature("anything", "off", "n/a", "error", "x"))
    assert seen == [(3, "anything[sphere=off,eps=n/a]", 2.5), (3, "anything[sphere=off,eps=n/a]", oracle.DEFAULT_TIMEOUT)]


def test_timeouts_and_crashes_are_never_reproduced_in_process(monkeypatch):
    import hullstress.runner as runner

    monkeypatch.delattr(runner, "run_one", raising=False)
    case = Case.from_points([[0, 0], [1, 0], [0, 1]])
    for check in ("timeout", "crash"):
        with pytest.raises(IsolationUnavailable, match="run_one"):
            oracle.fails_same_way(case, AlgorithmConfig("x"), Signature("x", "off", "n/a", check, "f"))
