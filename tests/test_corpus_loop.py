"""The whole regression loop through the command line, with a plug-in whose bug is planted, then fixed."""

import json
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

PY = sys.executable

PLUGIN = textwrap.dedent(
    """
    import numpy as np
    from scipy.spatial import ConvexHull
    from hullstress import register_algorithm

    MODE = {mode!r}

    @register_algorithm("planted-2d", dim=2)
    def planted(points):
        '''Qhull's 2D hull, with a planted bug: from 6 points on, the rightmost vertex is dropped.'''
        vertices = list(ConvexHull(points).vertices)
        if MODE == "raise" and len(points) >= 6:
            raise RuntimeError("planted regression")
        if MODE == "buggy" and len(points) >= 6:
            vertices.remove(max(vertices, key=lambda i: points[i, 0]))
        return vertices
    """
)


def outcome_of(stdout: str, config: str = "planted-2d[sphere=off,eps=n/a]") -> str:
    """The replay outcome printed for ``config`` (replay prints one line per non-ok pair; none means ok)."""
    lines = [l for l in stdout.splitlines() if config in l]
    return lines[0].split()[0] if lines else "ok"


def cli(*args, cwd):
    return subprocess.run([PY, "-m", "hullstress", *args], capture_output=True, text=True, cwd=cwd, timeout=600)


def _write_plugin(path: Path, mode: str) -> None:
    path.write_text(PLUGIN.format(mode=mode))


@pytest.fixture
def saved_corpus(tmp_path):
    plugin = tmp_path / "planted.py"
    _write_plugin(plugin, "buggy")
    corpus = tmp_path / "corpus"
    res = cli("run", "--plugin", str(plugin), "--algorithm", "planted-2d", "--generator", "uniform",
              "--sphere", "off", "--sizes", "40", "--save-corpus", str(corpus), "--out", str(tmp_path / "out"),
              "--workers", "1", "--quiet", cwd=tmp_path)
    assert res.returncode == 1, res.stdout + res.stderr
    assert "corpus: 1 new entries" in res.stdout
    return plugin, corpus


def test_planted_bug_is_saved_minimised_replayed_then_fixed(saved_corpus, tmp_path):
    plugin, corpus = saved_corpus
    files = sorted(corpus.glob("*.json"))
    assert len(files) == 1
    entry = json.loads(files[0].read_text())
    assert entry["provenance"]["family"] == "uniform" and entry["provenance"]["original_size"] == 40
    assert entry["shape"][0] <= 8  # shrunk from 40 points (the bug needs 6)
    assert entry["expectations"]["planted-2d[sphere=off,eps=n/a]"].startswith("fail containment")
    assert entry["label"] == "planted-2d[sphere=off,eps=n/a] " + entry["expectations"]["planted-2d[sphere=off,eps=n/a]"]
    # Every other config's verdict on the case is recorded too.
    assert "monotone-chain[sphere=off,eps=scaled]" in entry["expectations"]

    still = cli("replay", str(corpus), "--plugin", str(plugin), "--algorithm", "planted-2d", "--workers", "1", cwd=tmp_path)
    assert still.returncode == 0, still.stdout + still.stderr
    assert outcome_of(still.stdout) == "still-failing" and "0 entries with regressions" in still.stdout

    _write_plugin(plugin, "fixed")
    fixed = cli("replay", str(corpus), "--plugin", str(plugin), "--algorithm", "planted-2d", "--workers", "1", cwd=tmp_path)
    assert fixed.returncode == 0, fixed.stdout + fixed.stderr
    assert outcome_of(fixed.stdout) == "fixed" and "0 entries with regressions" in fixed.stdout

    _write_plugin(plugin, "raise")
    changed = cli("replay", str(corpus), "--plugin", str(plugin), "--algorithm", "planted-2d", "--workers", "1", cwd=tmp_path)
    assert changed.returncode == 1, changed.stdout + changed.stderr
    # Failing another way is reported as what it is (and exits 1: nobody has recorded this failure).
    assert outcome_of(changed.stdout) == "changed" and "1 entries with regressions" in changed.stdout
    assert "got error RuntimeError at " in changed.stdout
    assert "Traceback" not in changed.stderr

    # After the fix, --accept records the new verdicts; replay is then quiet.
    _write_plugin(plugin, "fixed")
    accepted = cli("replay", str(corpus), "--plugin", str(plugin), "--algorithm", "planted-2d", "--accept",
                   "--workers", "1", cwd=tmp_path)
    assert accepted.returncode == 0 and "accepted" in accepted.stdout
    accepted_entry = json.loads(files[0].read_text())
    assert accepted_entry["expectations"]["planted-2d[sphere=off,eps=n/a]"] == "pass"
    assert accepted_entry["state"] == "fixed"  # kept as a passing regression case; it holds its group no more


def test_baseline_run_fails_only_for_new_groups(saved_corpus, tmp_path):
    plugin, corpus = saved_corpus
    args = ["run", "--plugin", str(plugin), "--algorithm", "planted-2d", "--generator", "uniform", "--sphere", "off",
            "--sizes", "40", "--out", str(tmp_path / "out2"), "--workers", "1", "--quiet", "--no-shrink"]
    # Saved with --workers 1, compared in-process: the identity does not depend on the worker count.
    known = cli(*[a if a != "1" else "0" for a in args], "--baseline", str(corpus), cwd=tmp_path)
    assert known.returncode == 0, known.stdout + known.stderr
    assert "0 new" in known.stdout and "1 still-failing" in known.stdout
    # The bug fixed, but a time budget lets only each family's smallest case run: "not reached", never "fixed".
    _write_plugin(plugin, "fixed")
    budget = cli(*[a if a != "40" else "5,40" for a in args], "--baseline", str(corpus), "--time-budget", "0.001",
                 cwd=tmp_path)
    assert budget.returncode == 0, budget.stdout + budget.stderr
    assert "0 fixed, 1 not-reached" in budget.stdout and "  not-reached: planted-2d" in budget.stdout
    _write_plugin(plugin, "raise")
    new = cli(*args, "--baseline", str(corpus), cwd=tmp_path)
    assert new.returncode == 1 and "1 new" in new.stdout
    # The old group no longer happens (every case now raises first): fixed, confirmed on its corpus case.
    assert "1 fixed" in new.stdout and "  fixed: planted-2d[sphere=off,eps=n/a] fail containment" in new.stdout


def test_corrupt_corpus_files_are_named_and_the_rest_replays(saved_corpus, tmp_path):
    plugin, corpus = saved_corpus
    good = sorted(corpus.glob("*.json"))[0]
    text = good.read_text()
    (corpus / "truncated.json").write_text(text[: len(text) // 3])
    (corpus / "future.json").write_text(text.replace('"format_version": 2', '"format_version": 7'))
    res = cli("replay", str(corpus), "--plugin", str(plugin), "--algorithm", "planted-2d", "--workers", "1", cwd=tmp_path)
    assert res.returncode == 2, res.stdout + res.stderr
    errors = res.stderr.strip().splitlines()
    assert len(errors) == 2
    assert any("truncated.json" in e and "not valid JSON" in e for e in errors)
    assert any("future.json" in e and "unknown format version 7" in e for e in errors)
    assert outcome_of(res.stdout) == "still-failing" and "Traceback" not in res.stderr
