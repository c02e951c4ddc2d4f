"""``python -m hullstress run`` end to end: report files, exit statuses, bad input, determinism."""

import json
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from hullstress.cli import main
from hullstress.results import ROW_COLUMNS, TIMING_COLUMNS

PY = sys.executable


def run_cli(*args, cwd=None, timeout=300):
    return subprocess.run([PY, "-m", "hullstress", *args], capture_output=True, text=True, cwd=cwd, timeout=timeout)


def _run_dir(stdout: str) -> Path:
    line = [l for l in stdout.splitlines() if l.startswith("report: ")][-1]
    return Path(line.split("report: ", 1)[1])


GOOD_PLUGIN = textwrap.dedent(
    """
    import numpy as np
    from scipy.spatial import ConvexHull
    from hullstress import register_algorithm

    @register_algorithm("test-qhull-2d", dim=2)
    def qhull_2d(points):
        '''scipy's hull (correct on general position).'''
        return ConvexHull(points).vertices
    """
)


@pytest.fixture
def good_plugin(tmp_path):
    path = tmp_path / "good_plugin.py"
    path.write_text(GOOD_PLUGIN)
    return path


@pytest.fixture
def square_csv(tmp_path):
    path = tmp_path / "square.csv"
    pts = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.5, 0.5]])
    np.savetxt(path, pts, delimiter=",")
    return path


def test_points_file_only_run_writes_report_and_exits_0(tmp_path, good_plugin, square_csv):
    res = run_cli("run", "--plugin", str(good_plugin), "--algorithm", "test-qhull-2d",
                  "--points-file", str(square_csv), "--out", str(tmp_path / "out"), "--workers", "0")
    assert res.returncode == 0, res.stderr
    run_dir = _run_dir(res.stdout)
    assert run_dir.parent == tmp_path / "out"
    df = pd.read_csv(run_dir / "results.csv", keep_default_na=False)
    assert list(df.columns) == list(ROW_COLUMNS)
    assert len(df) == 1  # one case, sphere off: the default for a plug-in
    assert set(df["generator"]) == {"file"} and set(df["status"]) == {"pass"}
    meta = json.loads((run_dir / "run.json").read_text())
    assert meta["complete"] is True and meta["seed"] == 0 and "numpy" in meta["versions"]
    # Every phase's wall time, the report's included (run.json is written again after the report).
    assert {"generate", "sweep", "triage", "report"} <= set(meta["phase_seconds"])
    assert "[failures_by_config_family.csv](failures_by_config_family.csv)" in (run_dir / "summary.md").read_text()
    assert (run_dir / "failures_by_config_family.csv").is_file() and (run_dir / "status_by_config.csv").is_file()
    assert not (run_dir / "results.partial.csv").exists()


def test_failures_exit_1(tmp_path, square_csv):
    plugin = tmp_path / "bad_plugin.py"
    plugin.write_text(textwrap.dedent(
        """
        from hullstress import register_algorithm

        @register_algorithm("test-drops-a-corner", dim=2)
        def drops(points):
            return [0, 1, 2]          # the square's corner 3 is left out
        """
    ))
    res = run_cli("run", "--plugin", str(plugin), "--algorithm", "test-drops-a-corner", "--sphere", "off",
                  "--points-file", str(square_csv), "--out", str(tmp_path), "--workers", "0")
    assert res.returncode == 1, res.stderr
    df = pd.read_csv(_run_dir(res.stdout) / "results.csv", keep_default_na=False)
    assert df["status"].tolist() == ["fail"] and "containment" in df["failed_checks"][0]


def test_a_library_that_crashes_on_the_empty_set_gets_a_cause_with_no_points(tmp_path):
    """The bad-input family's empty case is triaged, foldered, reported and reproduced like any other."""
    plugin = tmp_path / "abort_plugin.py"
    plugin.write_text(textwrap.dedent(
        """
        import os
        from scipy.spatial import ConvexHull
        from hullstress import register_algorithm

        @register_algorithm("test-aborts-on-empty", dim=2)
        def aborts(points):
            if len(points) == 0:
                os.abort()
            return ConvexHull(points).vertices
        """
    ))
    junit = tmp_path / "junit.xml"
    res = run_cli("run", "--plugin", str(plugin), "--algorithm", "test-aborts-on-empty", "--generator", "bad-input",
                  "--out", str(tmp_path / "out"), "--workers", "1", "--junit", str(junit))
    assert res.returncode == 1, res.stderr
    assert "internal error" not in res.stderr
    run_dir = _run_dir(res.stdout)
    causes = pd.read_csv(run_dir / "causes.csv", keep_default_na=False)
    empty = causes[causes["minimal_size"] == 0]
    assert len(empty) == 1 and "SIGABRT" in empty["folder"].iloc[0]
    folder = run_dir / "failures" / Path(empty["folder"].iloc[0]).name
    assert np.load(folder / "points.npy").shape == (0, 2)
    assert "(no points: shape (0, 2))" in junit.read_text()
    assert "(no points: shape (0, 2))" in (run_dir / "report.html").read_text()
    again = run_cli("reproduce", str(folder))
    assert "the same failure as recorded" in again.stdout, again.stdout + again.stderr


BAD_CALLS = [
    (["run", "--algorithm", "no-such-hull"], "unknown algorithm 'no-such-hull'; valid names:"),
    (["run", "--generator", "no-such-family"], "unknown generator 'no-such-family'; valid names:"),
    (["run", "--sizes", "ten"], "--sizes must be comma-separated positive integers, got 'ten'"),
    (["run", "--sizes", "10,0"], "--sizes must be positive, got 0"),
    (["run", "--points-file", "/nonexistent/points.csv"], "/nonexistent/points.csv"),
    (["run", "--workers", "-1"], "argument --workers: must be at least 0, got '-1'"),
    (["run", "--timeout", "0"], "argument --timeout: must be a positive number of seconds, got '0'"),
    (["run", "--time-budget", "-5"], "argument --time-budget: must be a positive number of seconds, got '-5'"),
    (["run", "--plugin", "/nonexistent/plugin.py"], "--plugin '/nonexistent/plugin.py': no such file"),
    (["run", "--plugin", "no_such_module_xyz"], "no module named 'no_such_module_xyz'"),
    (["run", "--profile", "weekly"], "invalid choice: 'weekly'"),
    (["run", "--sphere", "maybe"], "invalid choice: 'maybe'"),
    (["run", "--seed", "abc"], "invalid int value: 'abc'"),
    (["list", "everything"], "invalid choice: 'everything'"),
    (["replay", "/nonexistent/corpus"], "corpus '/nonexistent/corpus': no such file or directory"),
    (["export", "/nonexistent/case.json", "--format", "csv"], "no such file"),
]


@pytest.mark.parametrize("argv, message", BAD_CALLS, ids=[" ".join(a) for a, _ in BAD_CALLS])
def test_bad_input_gives_one_line_and_exit_2(argv, message, capsys):
    code = main(argv)
    err = capsys.readouterr().err
    assert code == 2
    assert message in err
    assert len(err.strip().splitlines()) == 1, err
    assert "Traceback" not in err


def test_help_exits_0(capsys):
    assert main(["run", "--help"]) == 0
    out = capsys.readouterr().out
    for option in ("--profile", "--algorithm", "--generator", "--sphere", "--eps", "--sizes", "--seed",
                   "--workers", "--timeout", "--time-budget", "--plugin", "--points-file", "--out"):
        assert option in out


def test_malformed_points_file_and_unwritable_out(tmp_path, capsys):
    bad = tmp_path / "bad.csv"
    bad.write_text("x,y\n1,2\n3,oops\n")
    assert main(["run", "--points-file", str(bad)]) == 2
    err = capsys.readouterr().err
    assert "bad.csv" in err and len(err.strip().splitlines()) == 1
    blocker = tmp_path / "a-file"
    blocker.write_text("not a folder")
    good = tmp_path / "good.csv"
    good.write_text("0,0\n1,0\n0,1\n")
    assert main(["run", "--points-file", str(good), "--out", str(blocker / "sub"), "--workers", "0"]) == 2
    err = capsys.readouterr().err
    assert "--out" in err and "a-file" in err and len(err.strip().splitlines()) == 1


def _table_without_timing(run_dir: Path) -> pd.DataFrame:
    return pd.read_csv(run_dir / "results.csv", keep_default_na=False).drop(columns=list(TIMING_COLUMNS))


def test_quick_profile_determinism_across_worker_counts(tmp_path):
    """Two runs with the same seed give identical tables whatever --workers is (timings aside)."""
    families = ["uniform", "coplanar-grid", "duplicates", "bad-input", "kettner-classroom", "cube-faces"]
    args = ["run", "--seed", "5", "--out", str(tmp_path), "--quiet", "--sizes", "12", "--no-shrink"]
    args += [f"--generator={f}" for f in families]
    first = run_cli(*args, "--workers", "1")
    second = run_cli(*args, "--workers", "2")
    assert first.returncode in (0, 1) and second.returncode == first.returncode, first.stderr + second.stderr
    a, b = _table_without_timing(_run_dir(first.stdout)), _table_without_timing(_run_dir(second.stdout))
    assert len(a) >= 200
    pd.testing.assert_frame_equal(a, b)


@pytest.mark.slow
def test_default_quick_profile_runs_under_a_minute(tmp_path):
    res = run_cli("run", "--out", str(tmp_path), "--quiet")
    assert res.returncode in (0, 1), res.stderr
    meta = json.loads((_run_dir(res.stdout) / "run.json").read_text())
    assert meta["calls"] >= 200 and meta["timings"]["wall_seconds"] < 60


NICE_PROBE = textwrap.dedent(
    '''
    """Reports the niceness of the process it runs in (tests/test_cli_run.py)."""
    import atexit
    import os

    from hullstress import register_algorithm

    # The command's own process imports this file too: at its exit, its niceness.
    atexit.register(lambda: open(os.environ["NICE_PROBE_LOG"], "a").write(f"{os.getpid()} {os.nice(0)}\\n"))


    @register_algorithm("test-nice-probe", dim=2)
    def probe(points):
        raise ValueError(f"niceness {os.nice(0)}")
    '''
)


@pytest.mark.skipif(not hasattr(__import__("os"), "nice"), reason="the platform has no nice()")
def test_the_command_line_yields_the_cpu_to_its_workers_which_keep_their_priority(tmp_path):
    # `run` lowers its own priority by YIELD_NICENESS once the fork server runs; the workers,
    # forked from it, keep the priority the command started with.
    import os

    from hullstress.pipeline import YIELD_NICENESS

    plugin = tmp_path / "nice_probe.py"
    plugin.write_text(NICE_PROBE)
    start = os.nice(0)
    log = tmp_path / "niceness.log"
    command = subprocess.Popen([PY, "-m", "hullstress", "run", "--plugin", str(plugin), "--algorithm",
                                "test-nice-probe", "--generator", "uniform", "--sizes", "8", "--no-shrink",
                                "--workers", "1", "--out", str(tmp_path / "out"), "--quiet"],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                               env={**os.environ, "NICE_PROBE_LOG": str(log)})
    _, err = command.communicate(timeout=300)
    assert command.returncode == 1, err[-2000:]  # the probe raises: an error row, failures found
    (run_dir,) = (tmp_path / "out").iterdir()
    assert set(pd.read_csv(run_dir / "results.csv")["reason"]) == {f"ValueError: niceness {start}"}
    exits = dict(line.split() for line in log.read_text().splitlines())
    assert exits[str(command.pid)] == str(min(19, start + YIELD_NICENESS))


def test_the_partial_table_has_every_column_in_order_and_none_or_missing_as_empty(tmp_path):
    from hullstress.report.writer import RowStream
    from hullstress.results import ResultRow

    stream = RowStream(tmp_path)
    full = {c: f"v-{c}" for c in ROW_COLUMNS}
    stream(ResultRow(full))
    sparse = {"case_id": "abc", "status": "pass", "seconds": 0.25, "failed_checks": None, "not_a_column": "x"}
    stream(ResultRow(sparse))
    stream.close(remove=False)
    lines = (tmp_path / "results.partial.csv").read_bytes().split(b"\r\n")
    assert lines[0].decode() == ",".join(ROW_COLUMNS) and lines[-1] == b""
    assert lines[1].decode() == ",".join(f"v-{c}" for c in ROW_COLUMNS)
    assert lines[2].decode() == ",".join({"case_id": "abc", "status": "pass", "seconds": "0.25"}.get(c, "")
                                         for c in ROW_COLUMNS)
    assert stream.count == 2
