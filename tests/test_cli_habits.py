"""Habits of Qhull and pytest users: --last-failed / --failed-first, --qhull-options, quiet libraries,
writable arrays, clockwise conventions, and assertion helpers that hide their own frames."""

from __future__ import annotations

import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from hullstress import AlgorithmConfig, Case
from hullstress._registry import ALGORITHMS, get_algorithm
from hullstress.cli import main
from hullstress.evaluate import evaluate
from hullstress.previous import select_previous_failures
from hullstress.runner import RunnerOptions, Task, execute
from hullstress.runner._protocol import AlgorithmRef, ensure_algorithm

PLUGIN = textwrap.dedent(
    """
    import os
    import sys

    import numpy as np
    from scipy.spatial import ConvexHull

    from hullstress import register_algorithm


    @register_algorithm("habits-fails-on-big", dim=2)
    def fails_on_big(points):
        '''Correct on up to 10 points; drops a vertex on larger inputs.'''
        hull = ConvexHull(points).vertices
        return hull if len(points) <= 10 else hull[1:]


    @register_algorithm("habits-chatty", dim=2)
    def chatty(points):
        '''Correct, and noisy on every stream a library can use.'''
        print("stdout from python")
        print("stderr from python", file=sys.stderr)
        os.write(2, b"stderr from C-level write, run-id 12345\\n")
        return ConvexHull(points).vertices


    @register_algorithm("habits-writes-input", dim=2, writable=True)
    def writes_input(points):
        '''Sorts its input in place (as some libraries do), then hulls the original order.'''
        original = points.copy()
        points.sort(axis=0)
        return ConvexHull(original).vertices


    @register_algorithm("habits-writes-read-only", dim=2)
    def writes_read_only(points):
        '''The same, without asking for a writable array.'''
        points.sort(axis=0)
        return [0, 1, 2]
    """
)


@pytest.fixture
def plugin(tmp_path):
    path = tmp_path / "habits_plugin.py"
    path.write_text(PLUGIN)
    yield path
    for name in [n for n in ALGORITHMS.names() if n.startswith("habits-")]:
        ALGORITHMS.remove(name)


def _run_dir(stdout: str) -> Path:
    return Path([line for line in stdout.splitlines() if line.startswith("report: ")][-1].split("report: ", 1)[1])


def _task(case_id_sizes, configs=("a", "b")):
    return [Task(i, Case.from_points(np.random.default_rng(n).random((n, 2))), tuple(AlgorithmConfig(c) for c in configs))
            for i, n in enumerate(case_id_sizes)]


def _previous_run(out: Path, failed: list[tuple[str, str]]) -> None:
    run = out / "20250101-000000-quick-seed0"
    run.mkdir(parents=True)
    rows = [{"case_id": c, "config": cfg, "status": "fail"} for c, cfg in failed]
    rows.append({"case_id": "0000000000000000", "config": "x[sphere=off,eps=n/a]", "status": "pass"})
    pd.DataFrame(rows).to_csv(run / "results.csv", index=False)


def test_last_failed_and_failed_first_select_from_the_latest_run(tmp_path):
    tasks = _task([5, 6, 7])
    label = tasks[2].configs[1].label
    _previous_run(tmp_path, [(tasks[2].case.case_id, label)])
    only, note = select_previous_failures(tasks, tmp_path, "only")
    assert [(t.case.case_id, [c.label for c in t.configs]) for t in only] == [(tasks[2].case.case_id, [label])]
    assert "running the 1 calls that failed in 20250101-000000-quick-seed0" in note
    first, note = select_previous_failures(tasks, tmp_path, "first")
    assert [t.index for t in first] == [2, 0, 1] and all(len(t.configs) == 2 for t in first)
    nothing, note = select_previous_failures(tasks, tmp_path / "none", "only")
    assert nothing == tasks and "no previous run" in note


def test_last_failed_through_the_command_line(plugin, tmp_path, capsys):
    args = ["run", "--plugin", str(plugin), "--algorithm", "habits-fails-on-big", "--generator", "uniform",
            "--sizes", "8,16", "--sphere", "off", "--workers", "0", "--no-shrink", "--out", str(tmp_path)]
    assert main(args) == 1
    first = pd.read_csv(_run_dir(capsys.readouterr().out) / "results.csv", keep_default_na=False)
    failed = set(first.loc[first["status"] == "fail", "case_id"])
    assert failed and len(failed) < len(first)
    assert main(args + ["--last-failed"]) == 1
    out = capsys.readouterr()
    second = pd.read_csv(_run_dir(out.out) / "results.csv", keep_default_na=False)
    assert set(second["case_id"]) == failed and len(second) == len(failed)
    assert "note: --last-failed: running the" in out.err


def test_qhull_options_set_the_reference(plugin, tmp_path, capsys):
    args = ["run", "--plugin", str(plugin), "--algorithm", "habits-fails-on-big", "--generator", "uniform",
            "--sizes", "8", "--sphere", "off", "--workers", "0", "--no-shrink", "--out", str(tmp_path),
            "--qhull-options", "Qbb Qc Q12"]
    assert main(args) == 0
    table = pd.read_csv(_run_dir(capsys.readouterr().out) / "results.csv", keep_default_na=False)
    assert set(table["qhull_options"]) == {"Qt Qbb Qc Q12"}


@pytest.mark.parametrize("workers", ["0", "1"])
def test_a_librarys_output_goes_into_its_row_and_the_log_not_the_terminal(plugin, tmp_path, workers, capfd):
    args = ["run", "--plugin", str(plugin), "--algorithm", "habits-chatty", "--generator", "uniform",
            "--sizes", "8", "--sphere", "off", "--workers", workers, "--no-shrink", "--out", str(tmp_path)]
    assert main(args) == 0
    out = capfd.readouterr()
    assert "from python" not in out.out + out.err and "C-level" not in out.out + out.err
    run_dir = _run_dir(out.out)
    table = pd.read_csv(run_dir / "results.csv", keep_default_na=False)
    for text in ("stdout from python", "stderr from python", "stderr from C-level write, run-id <n>"):
        assert all(text in cell for cell in table["call_output"]), text
    log = (run_dir / "calls.log").read_text()
    assert log.count("== habits-chatty[sphere=off,eps=n/a] on case") == len(table)


def test_writable_arrays_on_request_read_only_otherwise(plugin):
    from hullstress.plugins import load_plugin

    load_plugin(str(plugin))
    case = Case.from_points(np.random.default_rng(3).random((12, 2)))
    assert evaluate(case, AlgorithmConfig("habits-writes-input")).status == "pass"
    refused = evaluate(case, AlgorithmConfig("habits-writes-read-only"))
    assert refused.status == "error" and "read-only" in refused["reason"]
    assert not case.points.flags.writeable  # the case itself is never handed out writable


def test_clockwise_flag_reaches_the_workers_for_built_ins_too():
    spec = get_algorithm("monotone-chain")
    try:
        ref = AlgorithmRef(name=spec.name, origin=spec.origin, module=spec.module, file=None, spec_pickle=b"",
                           clockwise=True)
        assert ensure_algorithm(ref) is None and get_algorithm("monotone-chain").clockwise
        square = Case.from_points([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
        rows = []
        from hullstress._registry import set_clockwise

        execute([Task(0, square, (AlgorithmConfig("monotone-chain", "off", "scaled"),))],
                RunnerOptions(workers=1, qhull=False), rows.append)
        assert rows[0].status == "fail"  # the worker reversed a correct counter-clockwise hull
        set_clockwise("monotone-chain", False)
        rows.clear()
        execute([Task(0, square, (AlgorithmConfig("monotone-chain", "off", "scaled"),))],
                RunnerOptions(workers=1, qhull=False), rows.append)
        assert rows[0].status == "pass"
    finally:
        ALGORITHMS.replace(spec)


def test_assertion_helpers_hide_their_frames(tmp_path):
    test = tmp_path / "test_hidden.py"
    test.write_text(textwrap.dedent(
        """
        from hullstress.testing import assert_valid_hull

        def test_square():
            assert_valid_hull([[0, 0], [1, 0], [1, 1], [0, 1]], [0, 1, 2])
        """
    ))
    res = subprocess.run([sys.executable, "-m", "pytest", str(test), "-p", "no:cacheprovider", "-q"],
                         capture_output=True, text=True, cwd=tmp_path, timeout=300)
    assert res.returncode == 1
    assert "assert_valid_hull([[0, 0]" in res.stdout  # the caller's line is shown
    assert "hullstress/testing.py" not in res.stdout  # the helper's own frames are not
