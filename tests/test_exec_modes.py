"""``--exec`` programs in spawn and persistent mode: same table, isolation kept, bad programs refused at once.

The persistent programs here are the kit's C example (drivers/examples/monotone_chain.c,
built with the C compiler) and tests/programs/planted_persistent.py (the
Python kit, with planted crashes, hangs and out-of-step answers by case size).
"""

from __future__ import annotations

import os
import shlex
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from hullstress import AlgorithmConfig, Case
from hullstress._registry import ALGORITHMS, register_executable
from hullstress.adapters.executable import ExecutableHull, probe
from hullstress.errors import UsageError
from hullstress.runner import RunnerOptions, Task, execute

from _processes import alive

PY = sys.executable
REPO = Path(__file__).resolve().parent.parent
PLANTED = REPO / "tests" / "programs" / "planted_persistent.py"
#: Columns that hold timings or what a program printed: they differ between any two runs.
VOLATILE = ["seconds", "check_seconds", "call_output"]


def run_cli(*args, env=None, timeout=300):
    return subprocess.run([PY, "-m", "hullstress", *args], capture_output=True, text=True, cwd=REPO,
                          env={**os.environ, **(env or {})}, timeout=timeout)


def _run_dir(stdout: str) -> Path:
    return Path([line for line in stdout.splitlines() if line.startswith("report: ")][-1].split("report: ", 1)[1])


@pytest.fixture(scope="module")
def monotone_chain(tmp_path_factory) -> str:
    """The C kit's example driver, built with the documented command into a temporary folder."""
    if shutil.which("make") is None or shutil.which(os.environ.get("CC", "cc")) is None:
        pytest.skip("needs make and a C compiler: apt-get install build-essential")
    build = tmp_path_factory.mktemp("drivers-build")
    res = subprocess.run(["make", "-C", str(REPO / "drivers"), "example", f"BUILD={build}"], capture_output=True,
                         text=True, timeout=300)
    assert res.returncode == 0, res.stderr
    return str(build / "monotone_chain")


def _table(res: subprocess.CompletedProcess) -> pd.DataFrame:
    assert res.returncode in (0, 1), res.stderr
    return pd.read_csv(_run_dir(res.stdout) / "results.csv", keep_default_na=False)


def test_spawn_and_persistent_modes_give_the_same_table(tmp_path, monotone_chain):
    tables = {}
    for mode in ("spawn", "persistent"):
        res = run_cli("run", "--exec", f"mc[dim=2,output=Fx,mode={mode}]={monotone_chain}", "--algorithm", "mc",
                      "--workers", "2", "--no-shrink", "--no-qhull", "--quiet", "--out", str(tmp_path / mode))
        tables[mode] = _table(res).drop(columns=VOLATILE)
    assert len(tables["spawn"]) >= 100
    pd.testing.assert_frame_equal(tables["spawn"], tables["persistent"])
    # The sweep found the example's real limits (its exact-equality sort on duplicates), not nothing.
    assert set(tables["spawn"]["status"]) >= {"pass", "fail"}


def test_run_json_and_the_report_name_what_ran(tmp_path, monotone_chain):
    import json

    res = run_cli("run", "--exec", f"mc[dim=2,output=Fx,mode=persistent]={monotone_chain}", "--algorithm", "mc",
                  "--generator", "uniform", "--workers", "1", "--no-shrink", "--no-qhull", "--quiet",
                  "--out", str(tmp_path / "out"))
    run_dir = _run_dir(res.stdout)
    meta = json.loads((run_dir / "run.json").read_text())
    assert meta["executables"]["mc"] == {"command": monotone_chain, "program": monotone_chain, "mode": "persistent",
                                         "driver": "monotone_chain example 1.0", "library": "none"}
    assert "monotone_chain example 1.0" in (run_dir / "summary.md").read_text()


def _planted_tasks(sizes: list[int]) -> list[Task]:
    rng = np.random.default_rng(5)
    config = (AlgorithmConfig("planted-persistent"),)
    return [Task(i, Case.from_points(rng.integers(0, 50, size=(n, 2)).astype(float)), config)
            for i, n in enumerate(sizes)]


@pytest.fixture
def planted(tmp_path):
    register_executable("planted-persistent", [PY, str(PLANTED), str(tmp_path / "hang.pid"), str(tmp_path / "starts")],
                        dim=2, output="Fx", mode="persistent")
    yield tmp_path
    ALGORITHMS.remove("planted-persistent")


def test_a_crash_a_hang_and_garbage_end_only_their_case(planted):
    sizes = [6, 12, 7, 13, 8, 14, 9, 15, 11, 16]
    rows: list = []
    stats = execute(_planted_tasks(sizes), RunnerOptions(workers=1, timeout=3.0, qhull=False), rows.append)
    by_size = {int(row["n_points"]): row for row in rows}
    assert by_size[7]["status"] == "crash" and "SIGSEGV" in by_size[7]["reason"], by_size[7].values
    assert by_size[8]["status"] == "timeout", (by_size[8]["reason"], by_size[8]["call_output"])
    # Out of step in persistent mode: restarted, and the case confirmed in spawn mode (where it is right).
    assert by_size[9]["status"] == "pass", by_size[9].values
    assert "out of step" in by_size[9]["call_output"] and "spawn mode" in by_size[9]["call_output"]
    assert by_size[11]["status"] == "error" and "too many points for my taste" in by_size[11]["reason"]
    for n in (6, 12, 13, 14, 15, 16):
        assert by_size[n]["status"] == "pass", by_size[n].values
    # The hung program died with its worker, and programs were restarted, not started per case:
    # the probe, the first, after the crash, after the timeout (a new worker), after the garbage,
    # plus the spawn-mode confirmation of the garbage case.
    pid = int((planted / "hang.pid").read_text())
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline and alive(pid):
        time.sleep(0.1)
    assert not alive(pid)
    starts = (planted / "starts").read_text().split()
    assert len(starts) == 6, starts
    assert stats.worker_restarts == 1


def test_the_memory_limit_holds_in_persistent_mode(planted):
    # The worker (NumPy, SciPy: about 500 MB of address space) and its program share no limit:
    # the program inherits the worker's RLIMIT_AS, and its 3 GB allocation fails.
    rows: list = []
    execute(_planted_tasks([10, 6]), RunnerOptions(workers=1, timeout=20.0, qhull=False, memory_limit_mb=1500),
            rows.append)
    by_size = {int(row["n_points"]): row for row in rows}
    assert by_size[10]["status"] == "error" and "MemoryError" in by_size[10]["reason"], by_size[10].values
    assert by_size[6]["status"] == "pass"


BAD_PROGRAMS = [
    ("missing", "no-such-hull-program-xyz", "program 'no-such-hull-program-xyz' not found on PATH"),
    ("exits", "false", "'false' exited with code 1 on a 5-point case in general position; no stderr"),
    ("silent", "true", "'true' printed nothing for a 5-point case in general position"),
    ("exits-at-start[mode=persistent]", "sh -c 'echo cannot load libfoo >&2; exit 3'",
     "exited at start (exited with code 3) before its handshake; stderr: cannot load libfoo"),
    ("no-handshake[mode=persistent]", "echo 4 faces", "its first line '4 faces' is not a handshake"),
    ("other-dim[mode=persistent]", shlex.join([PY, str(PLANTED)]),
     "speaks dim=2 in its handshake, registered with dim=3"),
]


@pytest.mark.parametrize("name, command, message", BAD_PROGRAMS, ids=[b[0] for b in BAD_PROGRAMS])
def test_bad_programs_are_refused_before_the_sweep(tmp_path, name, command, message):
    res = run_cli("run", "--exec", f"{name}={command}", "--algorithm", name.partition("[")[0],
                  "--out", str(tmp_path / "out"))
    assert res.returncode == 2, res.stderr
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and message in lines[0] and "Traceback" not in res.stderr, res.stderr
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())


def test_a_program_of_another_dimension_is_refused_in_spawn_mode(monotone_chain):
    # The kit's driver says so itself; a program without the kit is caught by its answer.
    with pytest.raises(UsageError, match="exited with code 2 on a 5-point case .* cannot read 2D points"):
        probe(ExecutableHull.from_command(monotone_chain, dim=3, output="i"))
    echo_2d_hull = ["sh", "-c", "cat >/dev/null; printf '4\\n0\\n1\\n2\\n3\\n'"]
    probe(ExecutableHull.from_command(echo_2d_hull, dim=2, output="Fx"))  # right for 2D: accepted
    with pytest.raises(UsageError, match="cannot be read as 'i' .* is it a 3D program writing 'i'"):
        probe(ExecutableHull.from_command(echo_2d_hull, dim=3, output="i"))


def test_a_program_that_never_answers_its_handshake_is_refused_in_time():
    hull = ExecutableHull.from_command(["sleep", "30"], dim=3, mode="persistent")
    started = time.monotonic()
    with pytest.raises(UsageError, match=r"never answered the handshake .* within 1 s"):
        probe(hull, timeout=1.0)
    assert time.monotonic() - started < 5


def test_the_probe_learns_the_version_in_both_modes(monotone_chain):
    for mode in ("spawn", "persistent"):
        hull = probe(ExecutableHull.from_command(monotone_chain, dim=2, output="Fx", mode=mode))
        assert (hull.driver, hull.library) == ("monotone_chain example 1.0", "none")
        assert "[monotone_chain example 1.0; none]" in hull.describe()


KIT_EXAMPLES = {
    "python": ([PY, str(REPO / "drivers" / "examples" / "scipy_driver.py")], 3, "i", "scipy "),
    "javascript": (["node", str(REPO / "drivers" / "examples" / "monotone_chain.mjs")], 2, "Fx", "none"),
}


@pytest.mark.parametrize("kit", sorted(KIT_EXAMPLES))
def test_the_kit_examples_hull_correctly_in_both_modes(kit):
    from hullstress.evaluate import evaluate

    command, dim, output, library = KIT_EXAMPLES[kit]
    if shutil.which(command[0]) is None:
        pytest.skip(f"needs {command[0]}: apt-get install nodejs")
    rng = np.random.default_rng(11)
    cases = [Case.from_points(rng.normal(size=(n, dim))) for n in (5, 40, 300)]
    for mode in ("spawn", "persistent"):
        name = f"kit-{kit}-{mode}"
        spec = register_executable(name, command, dim=dim, output=output, mode=mode)
        try:
            assert spec.func.library.startswith(library), spec.func
            for case in cases:
                row = evaluate(case, AlgorithmConfig(name), qhull=False)
                assert row["status"] == "pass", (mode, row["reason"])
        finally:
            ALGORITHMS.remove(name)
