"""``python -m hullstress reproduce FOLDER``: the verdict, the failed checks and the witness, and its exit status."""

from __future__ import annotations

import json
import shlex
import subprocess
import sys
import textwrap

import numpy as np
import pytest

from hullstress.case import Case
from hullstress.cli import main
from hullstress.config import AlgorithmConfig
from hullstress.plugins import load_plugin
from hullstress.report.failures import write_failure_folder
from hullstress.triage import run_config, shrink, signature_of
from hullstress.triage.stage import triage_one

PLUGIN = textwrap.dedent(
    '''
    """A plug-in whose bug goes away once a marker file exists (a "fix" the worker processes see)."""
    import os

    from scipy.spatial import ConvexHull

    from hullstress import register_algorithm

    MARKER = %r


    @register_algorithm("test-reproduce-drop", dim=2)
    def drop(points):
        """Qhull's polygon minus its first vertex, until fixed."""
        hull = [int(i) for i in ConvexHull(points).vertices]
        return hull if os.path.exists(MARKER) else hull[1:]
    '''
)


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("reproduce")
    marker = tmp / "fixed"
    plugin = tmp / "reproduce_plugin.py"
    plugin.write_text(PLUGIN % (str(marker),))
    load_plugin(str(plugin))
    rng = np.random.default_rng(2)
    case = Case(points=rng.uniform(-5, 5, size=(20, 2)), dim=2, family="test-cloud", seed=2, size=20)
    config = AlgorithmConfig("test-reproduce-drop")
    sig = signature_of(run_config(case, config, timeout=10))
    result = shrink(case, config, sig, timeout=10)
    rec = write_failure_folder(tmp / "failures", triage_one(result, config, timeout=10), plugins=[str(plugin)],
                               timeout=10.0, picture=False)
    return rec, marker


def test_reproduce_prints_the_verdict_the_checks_and_the_witness_with_coordinates(folder, capsys):
    rec, _ = folder
    assert main(["reproduce", str(rec.folder)]) == 1
    out = capsys.readouterr().out
    assert f"cause: {rec.signature.label}" in out
    # The severity with its reason: "(gross (... x DISTround))".
    assert f"failed checks: {rec.signature.checks} ({rec.signature.severity} (" in out
    assert "the same failure as recorded: it persists" in out
    witness = out.split("witness:\n", 1)[1]
    index = json.loads((rec.folder / "verdict.json").read_text())["offending"]["containment"][0]
    x, y = (float(v) for v in rec.points[index])
    assert f"containment: point {index} ({x!r}, {y!r})" in witness  # exact coordinates


def test_reproduce_txt_runs_with_this_interpreter_from_anywhere(folder, tmp_path):
    rec, _ = folder
    command = (rec.folder / "reproduce.txt").read_text().strip()
    argv = shlex.split(command)
    assert argv[:4] == [sys.executable, "-m", "hullstress", "reproduce"]
    proc = subprocess.run(argv, cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 1, proc.stderr[-2000:]
    assert "witness:" in proc.stdout


def test_reproduce_exits_0_once_the_bug_is_fixed(folder, capsys):
    rec, marker = folder
    marker.write_text("")
    try:
        assert main(["reproduce", str(rec.folder), "--all"]) == 0
        out = capsys.readouterr().out
        assert "no failure now (recorded: fail " in out
    finally:
        marker.unlink()


def test_save_corpus_keeps_the_minimal_case_with_its_provenance_and_replays_it(folder, tmp_path, capsys):
    from hullstress.corpus.replay import replay_corpus
    from hullstress.corpus.store import load_entry

    rec, _ = folder
    corpus = tmp_path / "corpus"
    assert main(["reproduce", str(rec.folder), "--save-corpus", str(corpus)]) == 1
    assert "corpus: new entry: " in capsys.readouterr().out
    [path] = sorted(corpus.glob("*.json"))
    entry = load_entry(path)
    assert np.array_equal(entry.case.points, rec.points)  # the minimal case, bit for bit
    assert entry.provenance["signature"] == rec.signature.slug
    assert entry.group == rec.signature and path.name == f"{rec.signature.group_id}.json"  # the group it holds
    assert entry.provenance["found_by"].startswith("hullstress reproduce ")
    assert entry.expectations["test-reproduce-drop[sphere=off,eps=n/a]"].startswith("fail")
    # Saving again adds nothing; replaying it finds the failure still failing.
    assert main(["reproduce", str(rec.folder), "--save-corpus", str(corpus)]) == 1
    assert "corpus: already there: " in capsys.readouterr().out
    assert len(list(corpus.glob("*.json"))) == 1
    result = replay_corpus(corpus, workers=0)
    assert set(result.table["outcome"]) <= {"still-failing", "ok"}


BAD = [
    (lambda tmp: tmp / "missing", "is not a folder"),
    (lambda tmp: tmp, "is not a failure folder (no case.json)"),
]


@pytest.mark.parametrize("where, message", BAD)
def test_not_a_failure_folder_is_a_one_line_error(where, message, tmp_path, capsys):
    assert main(["reproduce", str(where(tmp_path))]) == 2
    err = capsys.readouterr().err
    assert message in err and len(err.strip().splitlines()) == 1


def test_a_broken_case_json_is_a_one_line_error(tmp_path, capsys):
    (tmp_path / "case.json").write_text("{not json")
    assert main(["reproduce", str(tmp_path)]) == 2
    assert "cannot read" in capsys.readouterr().err
    (tmp_path / "case.json").write_text(json.dumps({"dim": 2}))
    assert main(["reproduce", str(tmp_path)]) == 2
    assert "has no 'signature'" in capsys.readouterr().err
