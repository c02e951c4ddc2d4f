"""The nightly workflow's own command lines, run night after night against a plug-in with a planted bug.

The commands are read from ``.github/workflows/nightly.yml`` (every ``python
-m hullstress`` line of the sweep job, continuation lines joined), run in a
temporary folder as the job runs them in a checkout, with a smaller selection
appended (one plug-in algorithm, one family, two sizes): the workflow's own
options (``--profile nightly --baseline tests/corpus --save-corpus
tests/corpus --junit ... --quiet``) stay as they are.

The loop must converge: night 1 on no corpus exits 1 and lists the new group,
nights 2 and 3 on the same code and seed exit 0 with "0 new"; a planted
regression exits 1 naming exactly the one new group; fixing the first bug is
reported fixed (exit 0), and replay says "fixed" (exit 0).
"""

from __future__ import annotations

import json
import re
import shlex
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

WORKFLOW = Path(__file__).resolve().parents[1] / ".github" / "workflows" / "nightly.yml"
CONFIG = "planted-2d[sphere=off,eps=n/a]"

PLUGIN = textwrap.dedent(
    """
    from scipy.spatial import ConvexHull
    from hullstress import register_algorithm

    BUGS = {bugs!r}

    @register_algorithm("planted-2d", dim=2)
    def planted(points):
        '''Qhull's 2D hull with planted bugs.'''
        vertices = list(ConvexHull(points).vertices)
        if "raise-on-large" in BUGS and len(points) >= 30:
            raise RuntimeError("planted regression")
        if "drop-rightmost" in BUGS and len(points) >= 6:
            vertices.remove(max(vertices, key=lambda i: points[i, 0]))
        return vertices
    """
)

#: Appended to every command: the plug-in and a small selection (the workflow's options are kept).
SELECTION = ("--plugin", "planted.py", "--algorithm", "planted-2d")
SWEEP_SELECTION = ("--generator", "uniform", "--sizes", "12,40")


def workflow_commands(text: str) -> list[list[str]]:
    """Every ``python -m hullstress`` command of the workflow, as argument lists, in file order."""
    logical, pending = [], ""
    for line in text.splitlines():
        stripped = line.strip()
        if stripped.startswith("- name:") or stripped.startswith("#"):
            pending = ""
            continue
        stripped = re.sub(r"^run:\s*", "", stripped)
        pending = f"{pending} {stripped}" if pending else stripped
        if pending.endswith("\\"):
            pending = pending[:-1].rstrip()
            continue
        logical.append(pending)
        pending = ""
    return [shlex.split(line) for line in logical if line.startswith("python -m hullstress ")]


def test_the_workflow_is_a_github_workflow_whose_commands_we_find():
    yaml = pytest.importorskip("yaml", reason="PyYAML parses the workflow file: pip install pyyaml")
    data = yaml.safe_load(WORKFLOW.read_text())
    steps = data["jobs"]["sweep"]["steps"]
    assert any(s.get("id") == "sweep" for s in steps) and True in data  # "on:" reads as True in YAML 1.1
    commands = workflow_commands(WORKFLOW.read_text())
    assert [c[3] for c in commands] == ["run", "replay"]
    sweep = commands[0]
    assert sweep[sweep.index("--baseline") + 1] == sweep[sweep.index("--save-corpus") + 1] == "tests/corpus"


def _night(tmp: Path, command: list[str]) -> subprocess.CompletedProcess:
    extra = SELECTION + (SWEEP_SELECTION if command[3] == "run" else ())
    return subprocess.run([sys.executable, *command[1:], *extra], capture_output=True, text=True, cwd=tmp,
                          timeout=600)


def _listed(stdout: str, state: str) -> list[str]:
    return [line.split(": ", 1)[1] for line in stdout.splitlines() if line.startswith(f"  {state}: ")]


def _corpus_files(corpus: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(corpus.glob("*.json"))}


def test_three_nights_converge_then_a_regression_and_a_fix(tmp_path):
    sweep, replay = workflow_commands(WORKFLOW.read_text())
    plugin = tmp_path / "planted.py"
    plugin.write_text(PLUGIN.format(bugs={"drop-rightmost"}))
    corpus = tmp_path / "tests" / "corpus"
    assert not corpus.exists()

    def night() -> tuple[subprocess.CompletedProcess, subprocess.CompletedProcess]:
        """The job's two hullstress steps; the job fails when either exits non-zero (its last step)."""
        run, rep = _night(tmp_path, sweep), _night(tmp_path, replay)
        for res in (run, rep):
            assert "Traceback" not in res.stderr, res.stderr
        return run, rep

    runs, replays, corpora = [], [], []
    for _ in range(3):
        run, rep = night()
        runs.append(run)
        replays.append(rep)
        corpora.append(_corpus_files(corpus))
    assert [r.returncode for r in runs] == [1, 0, 0], [r.stdout + r.stderr for r in runs]
    assert [r.returncode for r in replays] == [0, 0, 0], [r.stdout + r.stderr for r in replays]
    # Night 1: one entry per failure group, each listed as new, each still failing on replay.
    entries = [json.loads(b) for b in corpora[0].values()]
    groups = _listed(runs[0].stdout, "new")
    assert len(entries) == len(groups) == 1 and "1 new," in runs[0].stdout
    assert [e["label"] for e in entries] == groups and entries[0]["state"] == "failing"
    assert entries[0]["shape"][0] <= 8  # the minimal case, not a 12- or 40-point case
    assert "1 still-failing, 0 fixed, 0 changed, 0 new-failure" in replays[0].stdout
    # Nights 2 and 3: "0 new", and the corpus is left byte for byte as it was (no change to propose).
    for run in runs[1:]:
        assert "0 new, 1 still-failing, 0 fixed, 0 not-reached" in run.stdout and "corpus: 0 new entries" in run.stdout
    assert corpora[0] == corpora[1] == corpora[2]
    assert (tmp_path / "reports" / "junit.xml").is_file()

    # A planted regression: exactly one new group, the known one still failing; replay stays green.
    plugin.write_text(PLUGIN.format(bugs={"drop-rightmost", "raise-on-large"}))
    run, rep = night()
    assert run.returncode == 1 and rep.returncode == 0, run.stdout + run.stderr + rep.stdout
    new = _listed(run.stdout, "new")
    assert len(new) == 1 and new[0].startswith(f"{CONFIG} error RuntimeError at "), run.stdout
    assert "1 new, 1 still-failing, 0 fixed" in run.stdout
    assert len(_corpus_files(corpus)) == 2

    # The first bug fixed: reported fixed by name, exit 0; replay says fixed too, exit 0.
    plugin.write_text(PLUGIN.format(bugs={"raise-on-large"}))
    run, rep = night()
    assert run.returncode == 0, run.stdout + run.stderr
    assert "0 new, 1 still-failing, 1 fixed, 0 not-reached" in run.stdout
    assert _listed(run.stdout, "fixed") == groups
    assert rep.returncode == 0, rep.stdout + rep.stderr
    assert "1 still-failing, 1 fixed, 0 changed, 0 new-failure" in rep.stdout
