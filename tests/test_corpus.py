"""Regression corpus format, de-duplication, atomic writes, corrupt files, classification, baseline."""

import math
import multiprocessing as mp

import numpy as np
import pandas as pd
import pytest

from hullstress.corpus.baseline import compare_with_baseline, failure_groups, load_baseline
from hullstress.case import Case
from hullstress.corpus.store import (
    CorpusEntry,
    iter_corpus,
    load_entry,
    row_signature,
    save_entry,
)
from hullstress.errors import CorpusError, UsageError
from hullstress.corpus.replay import classify

SPECIALS = [
    [0.1, -0.0],
    [float("nan"), float("inf")],
    [-float("inf"), 5e-324],
    [1.7976931348623157e308, math.nextafter(1.0, 2.0)],
]


def _entry(points, **kw):
    case = Case(points=np.array(points, dtype=np.float64), dim=2, family="fam", params={"k": 1}, seed=7, size=4)
    return CorpusEntry(case=case, expectations={"a[sphere=off,eps=n/a]": "fail:containment"}, provenance={"family": "fam", "params": {"k": 1}, "seed": 7}, **kw)


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
        (lambda text: text.replace('"format_version": 1', '"format_version": 99'), "unknown format version 99"),
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
        ("fail:containment", "fail:containment", "still-failing"),
        ("fail:containment", "pass", "fixed"),
        ("error", "rejected", "fixed"),
        ("fail:containment", "fail:convexity", "changed"),
        ("crash", "timeout", "changed"),
        ("pass", "error", "new-failure"),
        (None, "fail:manifoldness", "new-failure"),
        ("rejected", "pass", "ok"),
        (None, "pass", "ok"),
    ],
)
def test_classify(expected, actual, outcome):
    assert classify(expected, actual) == outcome


@pytest.mark.parametrize(
    "row, signature",
    [
        ({"status": "pass"}, "pass"),
        ({"status": "crash", "reason": "killed by signal 11"}, "crash"),
        ({"status": "fail", "reason": "output contract: face 0 ...", "failed_checks": ""}, "fail:contract"),
        ({"status": "fail", "reason": "x", "failed_checks": "containment,convexity"}, "fail:convexity"),
        ({"status": "fail", "reason": "returned a hull for invalid input", "failed_checks": ""}, "fail:invalid-input"),
    ],
)
def test_row_signature(row, signature):
    assert row_signature(row) == signature


def _table(rows):
    base = {"reason": "", "failed_checks": ""}
    return pd.DataFrame([{**base, **r} for r in rows])


def test_baseline_new_still_and_fixed(tmp_path):
    old = _table([
        {"algorithm": "a", "sphere": "off", "eps": "n/a", "generator": "g1", "status": "fail", "failed_checks": "containment"},
        {"algorithm": "a", "sphere": "off", "eps": "n/a", "generator": "g2", "status": "error"},
        {"algorithm": "b", "sphere": "on", "eps": "n/a", "generator": "g1", "status": "crash"},  # b not run now
    ])
    new = _table([
        {"algorithm": "a", "sphere": "off", "eps": "n/a", "generator": "g1", "status": "fail", "failed_checks": "containment"},
        {"algorithm": "a", "sphere": "off", "eps": "n/a", "generator": "g2", "status": "pass"},
        {"algorithm": "a", "sphere": "off", "eps": "n/a", "generator": "g3", "status": "timeout"},
    ])
    old.to_csv(tmp_path / "results.csv", index=False)
    cmp = compare_with_baseline(new, load_baseline(tmp_path))
    states = {(r.generator, r.signature): r.state for r in cmp.itertuples()}
    assert states == {("g3", "timeout"): "new", ("g1", "fail:containment"): "still-failing", ("g2", "error"): "fixed"}
    assert len(failure_groups(new)) == 2


def test_baseline_from_corpus_and_bad_paths(tmp_path):
    save_entry(tmp_path, _entry([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]))
    groups = load_baseline(tmp_path)
    assert groups[["algorithm", "generator", "signature"]].values.tolist() == [["a", "fam", "fail:containment"]]
    with pytest.raises(UsageError, match="no such file"):
        load_baseline(tmp_path / "missing")
    (tmp_path / "x.txt").write_text("hi")
    with pytest.raises(UsageError, match="expected a run folder"):
        load_baseline(tmp_path / "x.txt")


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
