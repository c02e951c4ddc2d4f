"""Regression corpus format, de-duplication, atomic writes, corrupt files, classification, baseline."""

import math
import multiprocessing as mp

import numpy as np
import pandas as pd
import pytest

from hullstress.corpus.baseline import compare_with_baseline, load_baseline
from hullstress.case import Case
from hullstress.corpus.store import (
    CorpusEntry,
    held_groups,
    iter_corpus,
    load_entry,
    save_entry,
)
from hullstress.errors import CorpusError, UsageError
from hullstress.corpus.replay import classify
from hullstress.triage.signature import Signature, verdict_of

SPECIALS = [
    [0.1, -0.0],
    [float("nan"), float("inf")],
    [-float("inf"), 5e-324],
    [1.7976931348623157e308, math.nextafter(1.0, 2.0)],
]


def _entry(points, **kw):
    case = Case(points=np.array(points, dtype=np.float64), dim=2, family="fam", params={"k": 1}, seed=7, size=4)
    return CorpusEntry(case=case, expectations={"a[sphere=off,eps=n/a]": "fail containment (gross)"}, provenance={"family": "fam", "params": {"k": 1}, "seed": 7}, **kw)


def test_round_trip_is_bit_exact_including_nan_inf_and_signed_zero(tmp_path):
    entry = _entry(SPECIALS)
    path, written = save_entry(tmp_path, entry)
    assert written and path.name == f"{entry.entry_id}.json"
    back = load_entry(path)
    assert back.case.points.tobytes() == entry.case.points.tobytes()
    assert back.case.content_hash == entry.case.content_hash
    assert back.expectations == entry.expectations
    assert back.case.family == "fam" and back.case.seed == 7


def test_odd_shapes_round_trip(tmp_path):
    case = Case(points=np.array([1.0, 2.0, 3.0]), dim=3, family="bad-input")
    path, _ = save_entry(tmp_path, CorpusEntry(case=case))
    assert load_entry(path).case.points.shape == (3,)


def test_dedup_by_content_hash(tmp_path):
    a = _entry(SPECIALS)
    b = CorpusEntry(case=Case(points=a.case.points, dim=2, family="other"), expectations={})
    assert save_entry(tmp_path, a)[1] is True
    path, written = save_entry(tmp_path, b)
    assert written is False and load_entry(path).case.family == "fam"
    assert len(list(tmp_path.glob("*.json"))) == 1


def _writer(directory, seed):
    rng = np.random.default_rng(seed % 3)  # three distinct cases, each written by several processes
    pts = rng.random((50, 2))
    case = Case(points=pts, dim=2, family="concurrent")
    for _ in range(20):
        save_entry(directory, CorpusEntry(case=case, expectations={"x[sphere=off,eps=n/a]": "pass"}), overwrite=True)


def test_concurrent_writers_never_leave_a_corrupt_file(tmp_path):
    ctx = mp.get_context("fork")
    procs = [ctx.Process(target=_writer, args=(str(tmp_path), s)) for s in range(6)]
    for p in procs:
        p.start()
    for p in procs:
        p.join(30)
        assert p.exitcode == 0
    files = sorted(tmp_path.glob("*.json"))
    assert len(files) == 3
    for f in files:
        load_entry(f)  # every file parses and matches its content hash
    assert not list(tmp_path.glob(".*"))  # no temporary left behind


@pytest.mark.parametrize(
    "mutate, message",
    [
        (lambda text: text[: len(text) // 2], "not valid JSON"),
        (lambda text: text.replace('"format_version": 2', '"format_version": 99'), "unknown format version 99"),
        (lambda text: text.replace('"format_version": 2', '"format_version": 1'), "predates failure groups"),
        (lambda text: text.replace('"state": "failing"', '"state": "gone"'), "state must be one of"),
        (lambda text: text.replace('"hullstress-corpus"', '"something-else"'), "not a hullstress corpus file"),
        (lambda text: text.replace('"0.1"', '"0.2"'), "content hash"),
        (lambda text: text.replace('"shape": [\n  4,\n  2\n ]', '"shape": [3, 3]'), "malformed entry"),
    ],
)
def test_corrupt_files_give_one_clear_error_naming_the_file(tmp_path, mutate, message):
    good = _entry([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    bad = _entry(SPECIALS)
    save_entry(tmp_path, good)
    path, _ = save_entry(tmp_path, bad)
    path.write_text(mutate(path.read_text()))
    items = dict(iter_corpus(tmp_path))
    assert isinstance(items[path], CorpusError)
    text = str(items[path])
    assert message in text and path.name in text and "\n" not in text
    others = [v for k, v in items.items() if k != path]
    assert len(others) == 1 and isinstance(others[0], CorpusEntry)


@pytest.mark.parametrize(
    "expected, actual, outcome",
    [
        ("fail containment (gross)", "fail containment (gross)", "still-failing"),
        ("fail containment (gross)", "pass", "fixed"),
        ("error KeyError at m:3 in f", "rejected", "fixed"),
        ("fail containment (gross)", "fail containment (roundoff)", "changed"),
        ("fail containment (gross)", "fail convexity (gross)", "changed"),
        ("crash SIGSEGV", "timeout", "changed"),
        ("pass", "error KeyError at m:3 in f", "new-failure"),
        (None, "fail manifoldness (gross)", "new-failure"),
        ("rejected", "pass", "ok"),
        (None, "pass", "ok"),
    ],
)
def test_classify(expected, actual, outcome):
    assert classify(expected, actual) == outcome


ROW = {"algorithm": "a", "sphere": "off", "eps": "n/a"}


@pytest.mark.parametrize(
    "row, verdict",
    [
        ({"status": "pass"}, "pass"),
        ({"status": "crash", "reason": "killed by signal 11 (SIGSEGV)"}, "crash SIGSEGV"),
        ({"status": "fail", "reason": "output contract: face 0 ...", "failed_checks": ""}, "fail contract"),
        ({"status": "fail", "reason": "x", "failed_checks": "containment,convexity", "severity": "gross"},
         "fail convexity,containment (gross)"),  # the report's order of checks, whatever the cell's
        ({"status": "fail", "reason": "returned a hull for invalid input", "failed_checks": ""}, "fail invalid-input"),
        ({"status": "error", "reason": "KeyError: 3", "error_frame": "m:3 in f", "stage": "preprocess"},
         "error in preprocess KeyError at m in f"),
    ],
)
def test_the_verdict_a_corpus_records_is_the_failure_signature(row, verdict):
    assert verdict_of({**ROW, **row}) == verdict


def _table(rows):
    base = {"reason": "", "failed_checks": "", "severity": "", "config": "", "n_points": 4}
    table = pd.DataFrame([{**base, "case_id": f"c{i}", **r} for i, r in enumerate(rows)])
    table["config"] = [Signature(r.algorithm, r.sphere, r.eps).config.label for r in table.itertuples()]
    return table


def _group_entry(points, signature, **kw):
    case = Case(points=np.array(points, dtype=np.float64), dim=2, family="fam")
    return CorpusEntry(case=case, expectations={signature.config.label: signature.what}, group=signature, **kw)


CONTAINMENT = Signature("a", "off", "n/a", checks="containment", severity="gross")
ERROR = Signature("a", "off", "n/a", status="error", error="KeyError")
CRASH_B = Signature("b", "on", "n/a", status="crash", error="SIGSEGV")
TRIANGLE = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]


def test_the_corpus_holds_one_entry_per_failure_group(tmp_path):
    assert save_entry(tmp_path, _group_entry(TRIANGLE, CONTAINMENT))[1] is True
    # Another case of the same group is not a second entry; the same case for another group is.
    assert save_entry(tmp_path, _group_entry(TRIANGLE + [[0.5, 0.5]], CONTAINMENT))[1] is False
    path, written = save_entry(tmp_path, _group_entry(TRIANGLE, ERROR))
    assert written and path.name == f"{ERROR.group_id}.json"
    assert set(held_groups(tmp_path)) == {CONTAINMENT, ERROR}
    # A fixed entry stays as a passing regression case but holds its group no more.
    fixed = load_entry(path).with_expectations({ERROR.config.label: "pass"}, "fixed")
    save_entry(tmp_path, fixed, overwrite=True)
    assert set(held_groups(tmp_path)) == {CONTAINMENT} and len(list(tmp_path.glob("*.json"))) == 2
    assert held_groups(tmp_path / "missing") == {}


def test_group_ids_do_not_depend_on_anything_but_the_signature():
    assert CONTAINMENT.group_id == Signature.from_dict(CONTAINMENT.as_dict()).group_id
    assert len({CONTAINMENT.group_id, ERROR.group_id, CRASH_B.group_id}) == 3


def test_baseline_new_still_fixed_and_not_reached(tmp_path):
    old = _table([
        {**ROW, "generator": "g1", "status": "fail", "failed_checks": "containment", "severity": "gross"},
        {**ROW, "generator": "g2", "status": "error", "reason": "KeyError: 3"},
        {"algorithm": "b", "sphere": "on", "eps": "n/a", "generator": "g1", "status": "crash",
         "reason": "killed by signal 11 (SIGSEGV)"},
    ])
    new = _table([
        {**ROW, "generator": "g2", "status": "fail", "failed_checks": "containment", "severity": "gross"},
        {**ROW, "generator": "g2", "status": "pass"},
        {**ROW, "generator": "g3", "status": "timeout"},
    ])
    old.to_csv(tmp_path / "results.csv", index=False)
    baseline = load_baseline(tmp_path)
    assert baseline.groups == {CONTAINMENT, ERROR, CRASH_B}
    label = CONTAINMENT.config.label
    cmp = compare_with_baseline(new, baseline, {label: 3})
    states = {(r.status, r.algorithm): r.state for r in cmp.itertuples()}
    # The family does not matter (g1 then, g2 now); b did not run now: left out.
    assert states == {("timeout", "a"): "new", ("fail", "a"): "still-failing", ("error", "a"): "fixed"}
    # A sweep cut short (4 calls planned, 3 ran) never calls a group fixed.
    short = compare_with_baseline(new, baseline, {label: 4})
    assert dict(zip(short["status"], short["state"]))["error"] == "not-reached"
    # A corpus group the sweep did not meet but whose case still fails so is still failing.
    still = compare_with_baseline(new, baseline, {label: 3}, recheck=lambda entries: {ERROR: True})
    assert dict(zip(still["status"], still["state"]))["error"] == "fixed"  # a run baseline has no entries to re-run


def test_baseline_from_corpus_and_bad_paths(tmp_path):
    corpus = tmp_path / "corpus"
    save_entry(corpus, _group_entry(TRIANGLE, ERROR))
    baseline = load_baseline(corpus)
    assert baseline.groups == {ERROR} and set(baseline.entries) == {ERROR}
    table = _table([{**ROW, "generator": "g", "status": "pass"}])
    rechecked = compare_with_baseline(table, baseline, {ERROR.config.label: 1}, recheck=lambda e: {ERROR: True})
    assert list(rechecked["state"]) == ["still-failing"]
    # The first night: the folder --save-corpus creates; an empty folder.
    assert load_baseline(tmp_path / "missing", may_be_created=True).groups == frozenset()
    (tmp_path / "empty").mkdir()
    assert load_baseline(tmp_path / "empty").groups == frozenset()
    with pytest.raises(UsageError, match="no such file"):
        load_baseline(tmp_path / "missing")
    (tmp_path / "x.txt").write_text("hi")
    with pytest.raises(UsageError, match="expected a run folder"):
        load_baseline(tmp_path / "x.txt")
    (corpus / "bad.json").write_text("{")
    with pytest.raises(UsageError, match="bad.json"):
        load_baseline(corpus)


def test_replay_of_recorded_configs_ignores_algorithms_registered_later(tmp_path):
    """The pytest plug-in replays what each entry recorded; a session's own plug-ins are no regression."""
    from hullstress.config import AlgorithmConfig
    from hullstress.corpus.replay import replay_corpus
    from hullstress.corpus.store import CorpusEntry, save_entry
    from hullstress.registry import ALGORITHMS, register_algorithm

    case = Case.from_points([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.2, 0.2]], family="test")
    recorded = AlgorithmConfig("monotone-chain", "off", "scaled")
    save_entry(tmp_path, CorpusEntry(case=case, expectations={recorded.label: "pass"}, provenance={"family": "test"}))

    @register_algorithm("test-corpus-always-wrong", dim=2)
    def always_wrong(points):
        return [0, 1]

    try:
        everything = replay_corpus(tmp_path, workers=0)
        recorded_only = replay_corpus(tmp_path, workers=0, recorded_only=True)
    finally:
        ALGORITHMS.remove("test-corpus-always-wrong")
    assert "test-corpus-always-wrong[sphere=off,eps=n/a]" in set(everything.table["config"])
    assert (everything.table["outcome"] == "new-failure").any()
    assert list(recorded_only.table["config"]) == [recorded.label]
    assert list(recorded_only.table["outcome"]) == ["ok"]


def test_two_groups_with_one_minimal_case_are_two_entries_and_both_replay(tmp_path):
    """Two configs' groups may shrink to the same points: one entry each, each replayed and classified."""
    from hullstress.config import AlgorithmConfig
    from hullstress.corpus.replay import replay_corpus

    case = Case.from_points([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.2, 0.2]], family="test")
    scaled, fixed = AlgorithmConfig("monotone-chain", "off", "scaled"), AlgorithmConfig("monotone-chain", "off", "fixed")
    for config in (scaled, fixed):
        group = Signature(config.algorithm, config.sphere, config.eps, status="crash", error="SIGSEGV")
        save_entry(tmp_path, CorpusEntry(case=case, expectations={config.label: group.what}, group=group))
    assert len(list(tmp_path.glob("*.json"))) == 2
    result = replay_corpus(tmp_path, workers=0, recorded_only=True)
    assert sorted(zip(result.table["config"], result.table["outcome"])) == [(fixed.label, "fixed"), (scaled.label, "fixed")]
    assert len(result.per_entry()) == 2


def test_a_plugin_error_is_the_same_group_wherever_the_plugin_file_lives():
    """The plug-in's module name hashes the file's absolute path; the identity keeps only the file's stem."""
    from hullstress.triage.signature import signature_of

    rows = [{**ROW, "status": "error", "reason": "RuntimeError: planted",
             "error_frame": f"hullstress_plugin_my_hull_{digest}:12 in hull"} for digest in ("0123456789ab", "ba9876543210")]
    first, second = (signature_of(r) for r in rows)
    assert first == second and first.frame == "my_hull in hull" and first.group_id == second.group_id
