"""Tests for hullstress.triage: signatures, grouping, ddmin, coordinate simplification, the oracle."""

from __future__ import annotations

import re
import textwrap

import numpy as np
import pandas as pd
import pytest
from hypothesis import example, given
from hypothesis import strategies as st

from hullstress.case import Case
from hullstress.config import AlgorithmConfig
from hullstress.results import ResultRow
from hullstress.plugins import load_plugin
from hullstress.triage import (IsolationUnavailable, Signature, canonical_form, canonical_key, failed_check,
                               group_failures, groups_frame, signature_of)
from hullstress.triage import oracle
from hullstress.triage.deletion import minimise_rows
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
        ("gift-wrap", "ZeroDivisionError"),
        ("my/alg", "Bad Error"),
        ("..", "../../etc"),
        ("alg:1", "fam*?"),
        ("x" * 300, "y"),
    ],
)
def test_slug_is_filesystem_safe(names):
    alg, err = names
    slug = Signature(alg, "on", "fixed", status="error", error=err, frame="m:1 in f").slug
    assert re.fullmatch(r"[A-Za-z0-9._-]+", slug), slug
    assert slug not in (".", "..") and not slug.startswith(".")
    assert len(slug) <= 160


def test_slugs_of_distinct_signatures_differ_even_after_sanitising():
    a = Signature("my/alg", "on", "fixed", checks="containment", severity="gross")
    b = Signature("my-alg", "on", "fixed", checks="containment", severity="gross")
    c = Signature("my alg", "on", "fixed", checks="containment", severity="gross")
    # Errors at two frames of the same function are two bugs: two folders.
    d = Signature("alg", "off", "n/a", status="error", error="KeyError", frame="m:10 in f")
    e = Signature("alg", "off", "n/a", status="error", error="KeyError", frame="m:12 in f")
    assert len({a.slug, b.slug, c.slug, d.slug, e.slug}) == 5


SIGNATURE_ROWS = [
    # row fields, expected (stage, status, checks, severity, error, frame)
    ({"status": "fail", "failed_checks": "qhull_agreement,containment", "severity": "gross"},
     ("algorithm", "fail", "containment,qhull_agreement", "gross", "", "")),
    ({"status": "fail", "reason": "output contract: index 9 out of range", "severity": None},
     ("algorithm", "fail", "contract", "", "", "")),
    ({"status": "fail", "reason": "returned a hull for invalid input (points contain NaN)"},
     ("algorithm", "fail", "invalid-input", "", "", "")),
    ({"status": "error", "reason": "ZeroDivisionError: division by zero", "error_frame": "m:3 in f"},
     ("algorithm", "error", "", "", "ZeroDivisionError", "m in f")),
    ({"status": "error", "reason": "internal: checker raised KeyError: 3", "stage": "check"},
     ("check", "error", "", "", "internal", "")),
    ({"status": "crash", "reason": "killed by signal 11 (SIGSEGV)"}, ("algorithm", "crash", "", "", "SIGSEGV", "")),
    ({"status": "crash", "reason": "exited with code 3"}, ("algorithm", "crash", "", "", "exit 3", "")),
    ({"status": "timeout", "reason": "exceeded 10.0 s"}, ("algorithm", "timeout", "", "", "", "")),
    ({"status": "fail", "failed_checks": "containment", "severity": "roundoff", "stage": "preprocess"},
     ("preprocess", "fail", "containment", "roundoff", "", "")),
    ({"status": "fail", "failed_checks": pd.NA, "reason": float("nan"), "stage": pd.NA, "severity": pd.NA},
     ("algorithm", "fail", "invalid-input", "", "", "")),
]


@pytest.mark.parametrize("fields, expected", SIGNATURE_ROWS)
def test_signature_of_a_row_keeps_stage_status_checks_severity_error_and_frame(fields, expected):
    row = {"algorithm": "alg", "sphere": "on", "eps": "fixed", "generator": "coplanar-grid", "reason": "",
           "failed_checks": "", **fields}
    sig = signature_of(ResultRow(row))
    assert (sig.stage, sig.status, sig.checks, sig.severity, sig.error, sig.frame) == expected
    assert sig.config == AlgorithmConfig("alg", "on", "fixed")
    assert signature_of(pd.Series(row)) == sig  # a table row gives the same signature
    assert Signature.from_dict(sig.as_dict()) == sig


def test_the_family_is_not_part_of_a_signature_but_the_frame_is():
    base = {"algorithm": "alg", "sphere": "off", "eps": "n/a", "status": "error", "reason": "KeyError: 3",
            "error_frame": "m:3 in f"}
    assert signature_of({**base, "generator": "a"}) == signature_of({**base, "generator": "b"})
    # The function and module that raised tell errors apart; the line does not (an edit above it
    # must not make a known failure "new" in a nightly loop).
    assert signature_of({**base, "error_frame": "m:3 in g"}) != signature_of(base)
    assert signature_of({**base, "error_frame": "n:3 in f"}) != signature_of(base)
    assert signature_of({**base, "error_frame": "m:40 in f"}) == signature_of(base)
    assert signature_of({**base, "reason": "ValueError: 3"}) != signature_of(base)
    assert signature_of({**base, "status": "pass"}) is None
    assert signature_of({**base, "status": "rejected"}) is None


def test_error_frame_is_the_innermost_frame_of_the_code_under_test(tmp_path):
    from hullstress.errors import code_frame
    from hullstress.evaluate import evaluate

    # An algorithm module that raises from a helper, through numpy: the helper's frame is the one.
    mod = tmp_path / "frame_plugin_mod.py"
    mod.write_text(textwrap.dedent('''
        import numpy as np
        from hullstress import register_algorithm

        def _helper(points):
            return np.linalg.inv(np.zeros((2, 2)))  # raises LinAlgError inside numpy

        @register_algorithm("test-frame-raiser", dim=2)
        def raiser(points):
            return _helper(points)
    '''))
    load_plugin(str(mod))
    row = evaluate(Case.from_points([[0, 0], [1, 0], [0, 1]]), AlgorithmConfig("test-frame-raiser"))
    assert row.status == "error" and row["reason"].startswith("LinAlgError")
    module, rest = row["error_frame"].split(":", 1)
    assert module.startswith("hullstress_plugin_") or module == "frame_plugin_mod"
    assert rest.endswith(" in _helper") and rest.split(" in ")[0].isdigit()
    # The identity names a plug-in file's module by its stem (the row's name also hashes where the file lives).
    assert signature_of(row).frame == "frame_plugin_mod in _helper"  # the column keeps the line, the identity not
    assert code_frame(None, "x") == ""


# --------------------------------------------------------------------------- grouping


def _table(rows):
    base = {"algorithm": "alg", "sphere": "off", "eps": "n/a", "generator": "fam", "reason": "",
            "failed_checks": "", "n_points": 10, "dim": 2}
    return pd.DataFrame([{**base, **r} for r in rows])


def test_group_failures_counts_smallest_representative_and_families():
    table = _table([
        {"case_id": "c1", "status": "fail", "failed_checks": "containment", "n_points": 50},
        {"case_id": "c2", "status": "fail", "failed_checks": "containment,qhull_agreement", "n_points": 8},
        {"case_id": "c3", "status": "fail", "failed_checks": "containment", "n_points": 8, "generator": "other"},
        {"case_id": "c4", "status": "pass"},
        {"case_id": "c5", "status": "rejected", "reason": "ValueError"},
        {"case_id": "c6", "status": "error", "reason": "KeyError: 3"},
        {"case_id": "c1", "status": "fail", "sphere": "on", "failed_checks": "convexity"},
        {"case_id": "c7", "status": "error", "generator": "other", "reason": "KeyError: 4", "n_points": 3},
    ])
    groups = group_failures(table)
    by = {(g.signature.sphere, g.signature.checks or g.signature.status): g for g in groups}
    assert set(by) == {("off", "containment"), ("off", "containment,qhull_agreement"), ("off", "error"),
                       ("on", "convexity")}
    cont = by[("off", "containment")]
    assert (cont.count, cont.cases) == (2, 2)
    assert cont.smallest_case_id == "c3" and cont.smallest_n_points == 8
    assert cont.representative_case_id == "c1"
    assert cont.families == (("fam", 1), ("other", 1))
    # Denominator: every call of alg[sphere=off], whatever the family.
    assert cont.calls == 7
    errors = by[("off", "error")]
    assert errors.count == 2 and errors.families == (("fam", 1), ("other", 1)) and errors.smallest_case_id == "c7"
    assert by[("on", "convexity")].calls == 1
    assert groups[0].count == 2  # most frequent first
    frame = groups_frame(groups)
    assert list(frame["failures"]) == [g.count for g in groups]
    assert frame.loc[0, "rate"] == pytest.approx(2 / 7, abs=1e-3)


def test_group_failures_skips_missing_cells_and_keeps_the_first_of_the_smallest_in_table_order():
    table = _table([
        {"case_id": "c1", "status": "error", "reason": "KeyError: 1", "n_points": 9},
        {"case_id": "c2", "status": "error", "reason": "KeyError: 2", "n_points": 4, "generator": None},
        {"case_id": "c3", "status": "error", "reason": "KeyError: 1", "n_points": 4, "generator": "other"},
        {"case_id": "c4", "status": "error", "reason": "KeyError: 3", "n_points": None},
    ]).astype({"generator": "string"})
    table.index = [40, 30, 20, 10]  # table order, not index order, decides ties
    (group,) = group_failures(table)
    assert group.count == 4 and group.case_ids == ("c1", "c2", "c3", "c4")
    assert group.smallest_case_id == "c4" and group.smallest_index == 10  # a missing size counts as 0
    assert group.families == (("fam", 2), ("other", 1))  # the missing family is counted nowhere
    assert group.reasons == ("KeyError: 1", "KeyError: 2", "KeyError: 3")


def test_group_failures_of_a_clean_or_empty_table():
    assert group_failures(_table([{"case_id": "a", "status": "pass"}, {"case_id": "b", "status": "rejected"}])) == []
    assert group_failures(_table([]).iloc[0:0]) == []


# --------------------------------------------------------------------------- deleting rows


@given(n=st.integers(2, 200), data=st.data())
def test_deletion_finds_exactly_the_planted_rows_in_few_questions(n, data):
    planted = data.draw(st.sets(st.integers(0, n - 1), min_size=1, max_size=min(n, 6)))
    calls = []

    def fails(subset):
        calls.append(subset)
        return planted <= set(subset)

    assert set(minimise_rows(n, fails)) == planted
    k = len(planted)
    # About k + 2 k log2(n / k) questions, plus the confirming walk.
    assert len(calls) <= 2 * k + 4 * k * (np.log2(n / k) + 1) + 4


def test_deletion_result_is_one_minimal_for_a_non_monotone_predicate():
    # Fails when the subset has an odd number of rows >= 3 including row 0 (not monotone).
    def fails(s):
        return 0 in s and len(s) >= 3 and len(s) % 2 == 1

    keep = minimise_rows(9, fails)
    assert fails(keep)
    assert all(not fails(tuple(i for i in keep if i != j)) for j in keep)


def test_deletion_respects_min_size_and_propagates_a_stop():
    assert len(minimise_rows(10, lambda s: True, min_size=4)) == 4

    class Stop(Exception):
        pass

    def stopper(s):
        raise Stop()

    with pytest.raises(Stop):
        minimise_rows(10, stopper)


def test_find_integer_is_exact_on_monotone_tests():
    from hullstress.triage.deletion import find_integer

    for limit in (0, 1, 3, 4, 5, 8, 13, 100):
        asked = []

        def test(k):
            asked.append(k)
            return (yield from _answer(k <= limit))

        steps = find_integer(test)
        try:
            next(steps)
            raise AssertionError("test() asks nothing")
        except StopIteration as done:
            assert done.value == limit
        assert len(asked) <= 6 + 2 * max(1, int(np.log2(limit + 1)))


def _answer(value):
    return value
    yield  # a generator that asks nothing


# --------------------------------------------------------------------------- canonical forms


def test_canonical_key_ignores_translation_pow2_scaling_row_and_axis_order():
    from generators.transforms import permute_axes, permute_rows, scale_pow2

    rng = np.random.default_rng(4)
    pts = rng.integers(-50, 50, size=(7, 3)).astype(np.float64) / 8
    key = canonical_key(pts)
    assert canonical_key(permute_rows(pts, rng).points) == key
    assert canonical_key(scale_pow2(pts, -5).points) == key
    assert canonical_key(permute_axes(pts, (2, 0, 1)).points) == key
    assert canonical_key(pts + np.array([3.0, -0.5, 1e6])) == key  # exact here: coordinates are dyadic
    assert canonical_key(scale_pow2(permute_rows(pts + 7.0, rng).points, 3).points) == key


def test_canonical_key_tells_different_inputs_apart():
    pts = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.25, 0.25]])
    key = canonical_key(pts)
    assert canonical_key(pts * 3.0) != key  # not a power of two
    moved = pts.copy()
    moved[3, 0] = np.nextafter(0.25, 1.0)
    assert canonical_key(moved) != key
    assert canonical_key(pts[:3]) != key
    assert canonical_key(np.vstack([pts, pts[:1]])) != key  # a duplicate row is another input
    nan = np.array([[0.0, np.nan], [1.0, 2.0]])
    assert canonical_key(nan) == canonical_key(nan[::-1]) != canonical_key(np.array([[0.0, np.nan], [1.0, 3.0]]))
    chiral = np.array([[0.0, 0.0], [4.0, 0.0], [0.0, 1.0], [1.0, 2.0]])
    assert canonical_form(chiral) != canonical_form(chiral * np.array([-1.0, 1.0]))


def test_canonical_key_of_inputs_without_an_exact_form_names_their_shape():
    """The bad-input family's empty set, shape (0, d), fails in its own right and has a key like any input."""
    keys = {canonical_key(a) for a in (np.zeros((0, 2)), np.zeros((0, 3)), np.zeros(0), np.zeros((3, 0)),
                                       np.array(5.0), np.array(6.0))}
    assert len(keys) == 6
    assert canonical_form(np.zeros((0, 3))) == ("raw", (0, 3), ())
    assert canonical_key(np.zeros((0, 2))) == canonical_key(np.zeros((0, 2)))


def _rational_form(points: np.ndarray) -> tuple:
    """The documented canonical form the plain way, with fractions (shares nothing with the code)."""
    import itertools
    from fractions import Fraction

    exact = [[Fraction(float(x)) for x in row] for row in points]
    d = points.shape[1]
    lows = [min(row[j] for row in exact) for j in range(d)]
    shifted = [[row[j] - lows[j] for j in range(d)] for row in exact]
    peak = max(x for row in shifted for x in row)
    if peak > 0:
        e = 0
        while Fraction(2) ** e > peak:
            e -= 1
        while Fraction(2) ** (e + 1) <= peak:
            e += 1
        shifted = [[x / Fraction(2) ** e for x in row] for row in shifted]
    return min(tuple(sorted(tuple(row[j] for j in perm) for row in shifted))
               for perm in itertools.permutations(range(d)))


_coordinate = st.one_of(st.integers(-8, 8).map(float), st.floats(-1e3, 1e3, allow_subnormal=True),
                        st.floats(-1e-300, 1e-300), st.sampled_from([1e300, -1e300, 5e-324, 0.1, 1 / 3]))


@given(st.integers(2, 3).flatmap(lambda d: st.lists(st.lists(_coordinate, min_size=d, max_size=d),
                                                       min_size=1, max_size=6)))
@example([[0.0, 0.0], [0.0, 0.0]])
@example([[1e300, -1e300], [5e-324, 0.0]])
def test_canonical_form_is_the_rational_form_over_one_power_of_two(rows):
    # The integer form must decode to exactly the documented rational form:
    # axis minima subtracted, the peak scaled into [1, 2), rows sorted, the least axis order.
    from fractions import Fraction

    pts = np.array(rows, dtype=np.float64)
    kind, d, s, form = canonical_form(pts)
    assert kind == "exact" and d == pts.shape[1]
    scale = Fraction(2) ** -s
    assert tuple(tuple(Fraction(x) * scale for x in row) for row in form) == _rational_form(pts)
    flat = [x for row in form for x in row]
    assert all(x == 0 for x in flat) or any(x % 2 for x in flat)  # reduced: one key per class


# --------------------------------------------------------------------------- coordinate simplification


finite = st.floats(allow_nan=False, allow_infinity=False)


@given(st.lists(st.floats(allow_subnormal=True), min_size=1, max_size=12))
@example([0.0, -0.0, float("inf"), float("nan"), 5e-324, 1.0, 0.1, -3.0, 2.0 ** 1023 * 1.5])
def test_mantissa_bits_counts_significant_binary_digits(values):
    # Significant digits of the exact integer mantissa; 0 for zeros and non-finite values.
    def digits(x: float) -> int:
        if x == 0 or x != x or x in (float("inf"), float("-inf")):
            return 0
        num, den = abs(x).as_integer_ratio()  # den a power of two, num odd unless den == 1
        while num % 2 == 0:
            num //= 2
        return num.bit_length()

    assert mantissa_bits(np.array(values)).tolist() == [digits(v) for v in values]


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
@example([5e-324])  # found by the default profile: the old check's ratio out / pts overflowed (2**1074)
@example([-1e-310, 3e-320, 0.0])
def test_pow2_normalize_is_exact_and_lands_in_1_2(values):
    pts = np.array(values).reshape(-1, 1)
    out = pow2_normalize(pts)
    if out is None:
        return
    m = np.max(np.abs(out))
    assert 1.0 <= m < 2.0
    # One power of two for every value (compared through exponents: a ratio can overflow for subnormals).
    nonzero = pts != 0
    shift = np.frexp(out[nonzero])[1] - np.frexp(pts[nonzero])[1]
    assert np.all(shift == shift[0]) and np.array_equal(np.ldexp(pts, int(shift[0])), out)


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

    def fake_run_one(case, config, *, timeout, facts=None, qhull=True, qhull_options=None):
        seen.append((case.n_points, config.label, timeout))
        return ResultRow({"algorithm": config.algorithm, "sphere": config.sphere, "eps": config.eps,
                          "generator": case.family, "status": "crash", "reason": "killed by signal 11 (SIGSEGV)",
                          "failed_checks": ""})

    monkeypatch.setattr(runner, "run_one", fake_run_one, raising=False)
    case = Case.from_points([[0, 0], [1, 0], [0, 1]])
    config = AlgorithmConfig("anything")
    crash = Signature("anything", "off", "n/a", status="crash", error="SIGSEGV")
    assert oracle.fails_same_way(case, config, crash, timeout=2.5)
    assert not oracle.fails_same_way(case, config, Signature("anything", "off", "n/a", status="error"))
    assert seen == [(3, "anything[sphere=off,eps=n/a]", 2.5), (3, "anything[sphere=off,eps=n/a]", oracle.DEFAULT_TIMEOUT)]


def test_timeouts_and_crashes_are_never_reproduced_in_process(monkeypatch):
    import hullstress.runner as runner

    monkeypatch.delattr(runner, "run_one", raising=False)
    case = Case.from_points([[0, 0], [1, 0], [0, 1]])
    for status in ("timeout", "crash"):
        with pytest.raises(IsolationUnavailable, match="run_one"):
            oracle.fails_same_way(case, AlgorithmConfig("x"), Signature("x", "off", "n/a", status=status))
