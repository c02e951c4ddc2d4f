"""The first hour of a new user (issue 32, "The first hour"): eight frictions, each run the way the user met it.

1. a clone named ``hullstress`` in the current folder shadows the installed package;
2. ``--workers 0`` killed by the code under test: a warning at start, ``crash.log``,
   ``results.partial.csv`` and ``python -m hullstress report RUN_FOLDER``;
3. ``--memory-limit`` below what a worker needs is refused; an accepted one is enforced;
4. Ctrl-C during the sweep names the command that triages what was found;
5. the terminal lists the algorithms' causes first, the sphere method's apart, each with its reproduce command;
6. severity is shown with its reason;
7. "did you mean" for every registry name;
8. input Qhull's format cannot carry is not given to a program (``--exec``).
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from hullstress.cli import main
from hullstress.options import DEFAULTS

PY = sys.executable
HOLDER = Path(__file__).resolve().parent / "programs" / "phase_holder.py"
#: A 2D program that hulls correctly (the probe at registration must accept it).
PLANTED_OK = f"{sys.executable} {Path(__file__).resolve().parent / 'programs' / 'planted_hull.py'} ok"


def _hullstress(*args: str, cwd: Path, env: dict[str, str] | None = None,
                timeout: float = 300) -> subprocess.CompletedProcess[str]:
    return subprocess.run([PY, "-m", "hullstress", *args], cwd=cwd, capture_output=True, text=True,
                          timeout=timeout, env={**os.environ, **(env or {})})


def _run_dir(out: Path) -> Path:
    (run_dir,) = [p for p in out.iterdir() if p.is_dir()]
    return run_dir


# -- 7. did you mean ----------------------------------------------------------------------------------------------

MISSPELLED = {
    "algorithm": (["run", "--algorithm", "monotone-chian"], "'monotone-chain'"),
    "generator": (["run", "--generator", "near-coplanr"], "'near-coplanar'"),
    "generator parameter": (["run", "--generator", "near-coplanar:dleta=1e-9"], "'delta'"),
    "executable": (["run", "--exec", f"my-qhull[dim=2,output=Fx]={PLANTED_OK}", "--algorithm", "my-qhul"],
                   "'my-qhull'"),
    "clockwise executable": (["run", "--exec", f"my-qhull[dim=2,output=Fx]={PLANTED_OK}", "--clockwise", "my-qhul"],
                             "'my-qhull'"),
    "profile": (["run", "--profile", "nigthly"], "'nightly'"),
    "check": (["shrink", "--algorithm", "jarvis-march", "--check", "convexty", "points.npy"], "'convexity'"),
    "transform": (["run", "--transform", "revers-rows"], "'reverse-rows'"),
    "sphere choice": (["run", "--sphere", "bth"], "'both'"),
    "subcommand": (["reprot"], "'report'"),
}


@pytest.mark.parametrize("what", list(MISSPELLED))
def test_a_misspelled_name_gets_one_line_with_a_did_you_mean(what, tmp_path, monkeypatch, capsys):
    argv, suggestion = MISSPELLED[what]
    monkeypatch.chdir(tmp_path)
    code = main([*argv, "--out", str(tmp_path / "out")] if argv[0] == "run" else argv)
    err = capsys.readouterr().err
    assert code == 2, err
    lines = [line for line in err.splitlines() if line.strip()]
    assert len(lines) == 1, err
    assert f"did you mean {suggestion}" in lines[0], lines[0]
    assert "Traceback" not in err


def test_the_profile_lookup_of_the_library_suggests_too():
    from hullstress.errors import UsageError
    from hullstress.options import get_profile

    with pytest.raises(UsageError, match="did you mean 'quick'"):
        get_profile("quik")


# -- 1. a clone named hullstress shadows the installed package -----------------------------------------------------

PLUGIN = '''
from scipy.spatial import ConvexHull
from hullstress import register_algorithm

@register_algorithm("my-chain", dim=2)
def my_chain(points):
    return ConvexHull(points).vertices
'''


@pytest.fixture
def clone_folder(tmp_path: Path) -> Path:
    """A folder holding a clone of the project named ``hullstress`` (its sources one level down) and a plug-in."""
    (tmp_path / "hullstress" / "hullstress").mkdir(parents=True)
    (tmp_path / "hullstress" / "pyproject.toml").write_text("[project]\nname = 'hullstress'\n")
    (tmp_path / "myhull.py").write_text(PLUGIN)
    probe = subprocess.run([PY, "-c", "import hullstress; print(getattr(hullstress, '__file__', None))"],
                           cwd=tmp_path, capture_output=True, text=True, timeout=60)
    if probe.stdout.strip() != "None":
        pytest.skip("hullstress is installed as a regular package here, which a folder cannot shadow "
                    "(only an editable install, `pip install -e .`, can be shadowed)")
    return tmp_path


def test_a_shadowing_clone_is_named_in_one_line_by_the_command_line(clone_folder):
    done = _hullstress("run", "--plugin", "myhull.py", "--algorithm", "my-chain", "--out", "r", cwd=clone_folder)
    lines = [line for line in done.stderr.splitlines() if line.strip()]
    assert done.returncode == 2, done.stderr
    assert len(lines) == 1, done.stderr
    assert str(clone_folder / "hullstress") in lines[0] and "shadows the installed hullstress package" in lines[0]
    assert not (clone_folder / "r").exists()


def test_a_shadowing_clone_is_named_by_a_plugin_import(clone_folder):
    code = ("from hullstress.plugins import load_plugin\n"
            "from hullstress.errors import UsageError\n"
            "try:\n    load_plugin('myhull.py')\nexcept UsageError as exc:\n    print(exc)\n")
    done = subprocess.run([PY, "-c", code], cwd=clone_folder, capture_output=True, text=True, timeout=60)
    assert done.stdout.startswith("--plugin 'myhull.py': import failed: the folder"), done.stdout + done.stderr
    assert str(clone_folder / "hullstress") in done.stdout and "shadows" in done.stdout


# -- 3. --memory-limit --------------------------------------------------------------------------------------------

def test_a_memory_limit_below_what_a_worker_needs_is_refused_naming_the_value_and_the_minimum(tmp_path, capsys):
    code = main(["run", "--memory-limit", "1", "--algorithm", "monotone-chain", "--generator", "collinear-line",
                 "--sizes", "8", "--no-shrink", "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert code == 2, err
    assert len(err.strip().splitlines()) == 1
    assert "'1'" in err and f"minimum of {DEFAULTS.min_memory_limit_mb:g} MiB" in err
    assert not (tmp_path / "out").exists()


MEMORY_PLUGIN = '''
import numpy as np
from scipy.spatial import ConvexHull
from hullstress import register_algorithm

LIMIT = {limit} * 2**20


def _hull_after_allocating(points, nbytes):
    block = np.ones(nbytes // 8)  # touched: every page is really taken
    assert block[-1] == 1.0
    del block
    return ConvexHull(points).vertices


@register_algorithm("alloc-above-limit", dim=2)
def above(points):
    return _hull_after_allocating(points, LIMIT + 8 * 2**20)


@register_algorithm("alloc-below-limit", dim=2)
def below(points):
    return _hull_after_allocating(points, LIMIT - 24 * 2**20)
'''


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="RLIMIT_AS is enforced on Linux only")
def test_an_accepted_memory_limit_is_enforced_just_above_it_and_not_just_below(tmp_path):
    limit = int(DEFAULTS.min_memory_limit_mb)
    (tmp_path / "memplug.py").write_text(MEMORY_PLUGIN.format(limit=limit))
    done = _hullstress("run", "--plugin", "memplug.py", "--algorithm", "alloc-above-limit", "--algorithm",
                       "alloc-below-limit", "--generator", "uniform", "--sizes", "8", "--memory-limit", str(limit),
                       "--workers", "1", "--no-shrink", "--no-qhull", "--out", "out", cwd=tmp_path)
    assert done.returncode in (0, 1), done.stderr
    table = pd.read_csv(_run_dir(tmp_path / "out") / "results.csv")
    above = table[table["algorithm"] == "alloc-above-limit"]
    below = table[table["algorithm"] == "alloc-below-limit"]
    assert len(above) and len(below)
    assert set(above["status"]) == {"error"}, above["reason"].tolist()
    assert all(f"--memory-limit {limit} MiB" in r for r in above["reason"]), above["reason"].tolist()
    assert set(below["status"]) == {"pass"}, below["reason"].tolist()


# -- 2. --workers 0 killed by the code under test, and `report` --------------------------------------------------

CRASHING_PLUGIN = '''
import os
import signal

import numpy as np
from scipy.spatial import ConvexHull
from hullstress import register_algorithm


@register_algorithm("fpe-chain", dim=2)
def fpe_chain(points):
    pts = np.asarray(points, dtype=float)
    if len(pts) > 12:  # as CGAL's SIGFPE on a NaN: the process dies
        os.kill(os.getpid(), signal.SIGFPE)
    hull = list(ConvexHull(pts).vertices)
    return hull[:-1]  # a planted bug: the last vertex is missing
'''


def test_a_crash_without_isolation_leaves_its_rows_and_the_report_command_makes_the_report(tmp_path):
    (tmp_path / "fpe.py").write_text(CRASHING_PLUGIN)
    done = _hullstress("run", "--plugin", "fpe.py", "--algorithm", "fpe-chain", "--generator", "uniform",
                       "--generator", "regular-polygon", "--sizes", "8,16", "--workers", "0", "--out", "out",
                       cwd=tmp_path)
    assert done.returncode in (-signal.SIGFPE, 128 + signal.SIGFPE), (done.returncode, done.stderr)
    run_dir = _run_dir(tmp_path / "out")
    # Said at start, before the crash: what a crash does and the command to run after it.
    warning = [line for line in done.stderr.splitlines() if "without isolation" in line]
    assert len(warning) == 1, done.stderr
    assert f"-m hullstress report {run_dir}" in warning[0] and "results.partial.csv" in warning[0]
    partial = pd.read_csv(run_dir / "results.partial.csv")
    assert len(partial) >= 2 and set(partial["n_points"]) == {8}
    assert "Floating point exception" in (run_dir / "crash.log").read_text()
    assert json.loads((run_dir / "run.json").read_text())["state"] == "running"

    report = _hullstress("report", str(run_dir), cwd=tmp_path / "out")  # from another folder than the run's
    assert report.returncode == 1, report.stderr
    meta = json.loads((run_dir / "run.json").read_text())
    assert meta["state"] == "crashed" and "fpe.py" in meta["crash"]
    assert meta["calls"] == len(partial) and meta["not_reached"]
    table = pd.read_csv(run_dir / "results.csv")
    assert len(table) == len(partial) and "fail" in set(table["status"])
    assert (run_dir / "report.html").is_file() and any((run_dir / "failures").iterdir())
    summary = (run_dir / "summary.md").read_text()
    assert "crashed" in summary and "Top causes" in summary
    assert "CAUSE 1:" in report.stdout and "the sweep ended crashed" in report.stderr


@pytest.mark.parametrize("make, message", [
    (lambda p: p / "missing", "no such folder"),
    (lambda p: (p / "a-file.txt").write_text("x") and p / "a-file.txt", "is not a run folder: it is a file"),
    (lambda p: (p / "empty").mkdir() or p / "empty", "is not a run folder: it has no run.json"),
])
def test_report_on_what_is_not_a_run_folder_is_one_line_and_exit_2(tmp_path, capsys, make, message):
    folder = make(tmp_path)
    code = main(["report", str(folder)])
    err = capsys.readouterr().err
    assert code == 2, err
    assert len(err.strip().splitlines()) == 1 and message in err and str(folder) in err


def test_report_on_a_folder_without_rows_names_what_is_missing(tmp_path, capsys):
    folder = tmp_path / "run"
    folder.mkdir()
    (folder / "run.json").write_text(json.dumps({"arguments": {"profile": "quick", "out": str(tmp_path)}}))
    assert main(["report", str(folder)]) == 2
    err = capsys.readouterr().err
    assert "neither results.csv nor results.partial.csv" in err


# -- 4. Ctrl-C during the sweep ---------------------------------------------------------------------------------

def test_ctrl_c_during_the_sweep_names_the_command_that_triages_what_was_found(tmp_path):
    out = tmp_path / "out"
    mark = tmp_path / "holding"
    args = [PY, "-m", "hullstress", "run", "--plugin", str(HOLDER), "--algorithm", "phase-holder", "--sphere", "off",
            "--sizes", "8,16", "--generator", "uniform", "--workers", "2", "--timeout", "30", "--no-qhull",
            "--out", str(out)]
    with open(tmp_path / "stderr.txt", "w") as stderr:
        proc = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=stderr, cwd=tmp_path,
                                env={**os.environ, "HOLD_PHASE": "sweep", "HOLD_MARK": str(mark)})
    try:
        deadline = time.monotonic() + 240
        while not mark.exists():
            assert proc.poll() is None and time.monotonic() < deadline, (tmp_path / "stderr.txt").read_text()
            time.sleep(0.05)
        time.sleep(0.2)
        proc.send_signal(signal.SIGINT)
        proc.wait(timeout=60)
    finally:
        proc.kill()
        proc.wait()
    err = (tmp_path / "stderr.txt").read_text()
    assert proc.returncode == 130, err
    run_dir = _run_dir(out)
    command = f"-m hullstress report {run_dir}"
    assert command in err and "not triaged" in err
    summary = (run_dir / "summary.md").read_text()
    assert command in summary and "kept no record" not in summary
    # The command does what it says: the failures found before Ctrl-C get their causes.
    report = _hullstress("report", str(run_dir), cwd=tmp_path, env={"HOLD_PHASE": "none"})
    assert report.returncode == 1, report.stderr
    assert "CAUSE 1:" in report.stdout
    assert json.loads((run_dir / "run.json").read_text())["state"] == "interrupted"
    assert "Top causes" in (run_dir / "summary.md").read_text()


# -- 5 and 6. the terminal's causes, by stage, with reproduce commands and severity reasons -------------------------

def test_the_terminal_lists_the_algorithms_causes_first_the_sphere_methods_apart_each_with_its_command(tmp_path):
    done = _hullstress("run", "--plugin", str(HOLDER), "--algorithm", "phase-holder", "--algorithm", "monotone-chain",
                       "--generator", "collinear-line", "--generator", "uniform", "--sizes", "8", "--sphere", "both",
                       "--out", "out", cwd=tmp_path, env={"HOLD_PHASE": "none"})
    assert done.returncode == 1, done.stderr
    lines = done.stdout.splitlines()
    rules = [i for i, line in enumerate(lines) if line.startswith("===")]
    titles = [lines[i] for i in rules]
    assert "short summary: top" in titles[0] and "causes in the algorithms" in titles[0], titles
    assert any("the sphere method: top" in t and "(stage preprocess)" in t for t in titles[1:]), titles
    method_rule = next(i for i in rules if "sphere method" in lines[i])
    cause_lines = [i for i, line in enumerate(lines) if line.startswith(("CAUSE ", "METHOD "))]
    assert cause_lines
    for i in cause_lines:
        own = lines[i].startswith("CAUSE ")
        assert (i < method_rule) == own, lines[i]
        assert (" in preprocess " in lines[i]) != own, lines[i]
        folder = lines[i + 1].strip()
        assert lines[i + 2].strip().startswith("reproduce: ") and lines[i + 2].endswith(
            f"-m hullstress reproduce {(tmp_path / folder).absolute()}"), lines[i:i + 3]
    # Severity with its reason wherever a cause shows it.
    graded = [i for i in cause_lines if "(gross" in lines[i] or "(roundoff" in lines[i]]
    assert graded and all("(gross (" in lines[i] or "(roundoff (" in lines[i] for i in graded), graded
    # ... and in what `reproduce` prints of the re-run.
    again = _hullstress("reproduce", lines[graded[0] + 1].strip(), cwd=tmp_path, env={"HOLD_PHASE": "none"})
    assert again.returncode == 1, again.stderr
    (checks,) = [line for line in again.stdout.splitlines() if line.strip().startswith("failed checks:")]
    assert "(gross (" in checks or "(roundoff (" in checks, checks


def test_the_pytest_helper_says_why_a_failure_is_gross():
    from hullstress.testing import assert_valid_hull

    # The unit square with its corner (1, 1) twice: every distance is 0, the polygon is no simple polygon.
    points = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [1.0, 1.0]])
    with pytest.raises(AssertionError) as info:
        assert_valid_hull(points, [0, 1, 2, 4, 3], qhull=False)
    message = str(info.value)
    assert "worst violation: gross (not a closed manifold, 0 x DISTround)" in message, message
    assert "gross, 0 x DISTround" not in message


@pytest.mark.parametrize("grade, distance, manifold, detail, shown", [
    ("roundoff", 0.0387, True, "containment: 1 points outside", "roundoff (0.0387 x DISTround)"),
    ("gross", 31.0, True, "containment: 1 points outside", "gross (31 x DISTround)"),
    ("gross", 0.0387, False, "manifoldness: clockwise orientation (signed area negative)",
     "gross (wrong orientation, 0.0387 x DISTround)"),
    ("gross", 0.0, False, "manifoldness: 2 repeated faces", "gross (not a closed manifold, 0 x DISTround)"),
    ("none", 0.0, True, "", "none"),
])
def test_severity_is_described_with_its_reason(grade, distance, manifold, detail, shown):
    from hullstress.checker.severity import describe_severity

    assert describe_severity(grade, distance, manifoldness=manifold, detail=detail) == shown


# -- 8. input Qhull's format cannot carry is not given to a program ----------------------------------------------

#: Logs the point count and finiteness of every input it is given; hulls only the probe's five points
#: (registration refuses a program that cannot hull at all) and declines everything else.
LOGGING_PROGRAM = f'''
import os, sys
sys.path.insert(0, {str(Path(__file__).resolve().parent / "programs")!r})
from planted_hull import hull, read_points
data = sys.stdin.read()
with open(os.environ["GIVEN_LOG"], "a") as fh:
    fh.write(data.split("\\n", 2)[1] + " " + ("nan" if "nan" in data or "inf" in data else "finite") + "\\n")
points = read_points(data)
if len(points) != 5:
    sys.exit(1)
answer = hull(points)
print(len(answer))
print("\\n".join(map(str, answer)))
'''


def test_a_program_is_not_given_input_that_qhulls_format_cannot_carry(tmp_path):
    (tmp_path / "logging_program.py").write_text(LOGGING_PROGRAM)
    log = tmp_path / "given.log"
    done = _hullstress("run", "--exec", f"logger[dim=2,output=Fx]={PY} logging_program.py", "--algorithm", "logger",
                       "--generator", "bad-input", "--no-shrink", "--out", "out", cwd=tmp_path,
                       env={"GIVEN_LOG": str(log)})
    assert done.returncode in (0, 1), done.stderr
    given = log.read_text().splitlines() if log.exists() else []
    assert given, "no case reached the program: the test proves nothing"
    for line in given:
        count, values = line.split()
        assert int(count) >= 2 and values == "finite", given
    table = pd.read_csv(_run_dir(tmp_path / "out") / "results.csv")
    kept_out = table[table["reason"].fillna("").str.contains("not given to the program")]
    kinds = {json.loads(p)["kind"] for p in kept_out["params"]}
    assert {"empty", "nan", "inf", "all-nan"} <= kinds, kinds
    assert set(kept_out["status"]) == {"rejected"}
