"""Programs as algorithms: ``--exec``, ``register_executable``, Qhull's formats, the real qconvex and rbox.

The planted-bug program (``tests/programs/planted_hull.py``) crashes, hangs,
writes garbage, wrong or out-of-range indices, exits non-zero or chatters on
stderr on request; each must end in its documented status.  The real
``qconvex`` (``pip install cmeel-qhull``) is swept through ``--exec`` beside
scipy's Qhull adapter and must get the same verdicts on the same cases.
"""

from __future__ import annotations

import io
import json
import os
import pickle
import shlex
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from hullstress import AlgorithmConfig, Case
from hullstress._registry import ALGORITHMS, register_executable
from hullstress.adapters.executable import ExecutableHull, locate_program, parse_exec_spec
from hullstress.cli import main
from hullstress.errors import ContractViolation, UsageError
from hullstress.evaluate import evaluate
from hullstress.qhull_format import format_fx, format_i, format_points, parse_hull

from _processes import alive

PY = sys.executable
PLANTED = Path(__file__).resolve().parent / "programs" / "planted_hull.py"
SQUARE = np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [0.0, 4.0], [1.0, 2.0], [2.0, 1.0], [3.0, 3.0]])


def run_cli(*args, cwd=None, env=None, timeout=300):
    return subprocess.run([PY, "-m", "hullstress", *args], capture_output=True, text=True, cwd=cwd,
                          env={**os.environ, **(env or {})}, timeout=timeout)


def _run_dir(stdout: str) -> Path:
    return Path([line for line in stdout.splitlines() if line.startswith("report: ")][-1].split("report: ", 1)[1])


def _planted(mode: str) -> str:
    return shlex.join([PY, str(PLANTED), mode])


@pytest.fixture(scope="module")
def qhull_programs() -> dict[str, str]:
    """Qhull's qconvex and rbox, installing cmeel-qhull from the registry when they are missing."""
    found = {name: locate_program(name) for name in ("qconvex", "rbox")}
    if None in found.values():
        subprocess.run([PY, "-m", "pip", "install", "--quiet", "cmeel-qhull"], capture_output=True, timeout=600)
        found = {name: locate_program(name) for name in ("qconvex", "rbox")}
    if None in found.values():
        pytest.skip("Qhull's programs are not installed and `pip install cmeel-qhull` failed (no network?)")
    return found  # type: ignore[return-value]


@pytest.fixture
def square_file(tmp_path) -> Path:
    path = tmp_path / "square.txt"
    path.write_text(format_points(SQUARE))
    return path


# -- Qhull's formats ------------------------------------------------------------------

UNREADABLE = [
    ("i", "", "the program wrote nothing"),
    ("i", "two\n0 1\n", "line 1 'two': expected the number of facets"),
    ("i", "3\n0 1\n1 2\n", "announces 3 facets, the output has 2 more lines"),
    ("i", "1\n0 1\n2 0\n", "line 3 '2 0': line 1 announced 1 facets; this line is one too many"),
    ("i", "2\n0 1\n1 x\n", "line 3 '1 x': 'x' is not an integer index"),
    ("i", "2\n0 1\n1 9\n", "line 3 '1 9': index 9 is out of range for 4 points"),
    ("i", "1\n0 1 2\n", "line 2 '0 1 2': a 2D facet is an edge of 2 indices, got 3"),
    ("i", "2\n0 1\n2 3\n", "the edges do not close into one polygon"),
    ("Fx", "2\n0 1\n3\n", "line 2 '0 1': expected one index per line, got 2"),
    ("Fx", "1\n-1\n", "index -1 is out of range"),
    ("off", "PLY\n", "line 1 'PLY': expected 'OFF'"),
]


@pytest.mark.parametrize("fmt, text, message", UNREADABLE, ids=[f"{f}:{t!r}" for f, t, _ in UNREADABLE])
def test_unreadable_output_names_the_line(fmt, text, message):
    with pytest.raises(ContractViolation, match="unreadable output") as info:
        parse_hull(text, fmt, SQUARE[:4])
    assert message in str(info.value)


def test_formats_round_trip_through_the_parser():
    square = SQUARE[:4]
    assert parse_hull(format_i([0, 1, 2, 3], 2), "i", square) == [0, 1, 2, 3]
    assert parse_hull(format_fx([3, 0, 1, 2]), "Fx", square) == [3, 0, 1, 2]
    cube = np.array([[x, y, z] for x in (0.0, 1.0) for y in (0.0, 1.0) for z in (0.0, 1.0)])
    faces = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]]
    assert parse_hull(format_i(faces, 3), "i", cube) == faces
    # OFF: vertices are matched by exact coordinates, whatever order the program lists them in.
    off = "OFF\n3 1 0\n0.0 1.0 1.0\n1.0 0.0 0.0\n0x0p+0 0.0 0.0\n3 0 1 2\n"
    assert parse_hull(off, "off", cube) == [[3, 4, 0]]
    with pytest.raises(ContractViolation, match="not exactly one of the input points"):
        parse_hull("OFF\n3 1 0\n0.5 0 0\n1 0 0\n0 0 0\n3 0 1 2\n", "off", cube)


EXEC_SPECS = [
    ("qconvex=qconvex Qt i", ("qconvex", "qconvex Qt i", {"dim": 3, "output": "i", "mode": "spawn"})),
    ("q2[dim=2,output=Fx]=qconvex Fx", ("q2", "qconvex Fx", {"dim": 2, "output": "Fx", "mode": "spawn"})),
    ("m[output=off]=my-hull --off", ("m", "my-hull --off", {"dim": 3, "output": "off", "mode": "spawn"})),
    ("p[dim=2,mode=persistent]=drv", ("p", "drv", {"dim": 2, "output": "i", "mode": "persistent"})),
]


@pytest.mark.parametrize("text, expected", EXEC_SPECS, ids=[t for t, _ in EXEC_SPECS])
def test_exec_specs_parse(text, expected):
    assert parse_exec_spec(text) == expected


BAD_EXEC_SPECS = [
    ("qconvex", "expected NAME=COMMAND"),
    ("=qconvex", "expected NAME=COMMAND"),
    ("q=", "expected NAME=COMMAND"),
    ("q[dim=4]=qconvex", "dim must be one of 2, 3, got '4'"),
    ("q[colour=red]=qconvex", "unknown option 'colour'; valid options: dim=2|3, output=i|Fx|off, "
                              "mode=spawn|persistent"),
    ("q[mode=fork]=qconvex", "mode must be one of spawn, persistent, got 'fork'"),
    ("q[output=o]=qconvex", "output must be one of i, Fx, off, got 'o'"),
]


@pytest.mark.parametrize("text, message", BAD_EXEC_SPECS, ids=[t for t, _ in BAD_EXEC_SPECS])
def test_bad_exec_specs_are_usage_errors(text, message):
    with pytest.raises(UsageError) as info:
        parse_exec_spec(text)
    assert message in str(info.value) and repr(text) in str(info.value)


def test_register_executable_checks_what_it_can_before_running_anything():
    with pytest.raises(UsageError, match="program 'no-such-hull-program' not found on PATH"):
        register_executable("t-exec-missing", "no-such-hull-program i", dim=3)
    with pytest.raises(UsageError, match="output 'Fx' lists extreme points, a hull only in 2D"):
        register_executable("t-exec-fx3", [PY, str(PLANTED), "ok"], dim=3, output="Fx")
    with pytest.raises(UsageError, match="No closing quotation"):
        register_executable("t-exec-quote", "qconvex 'i", dim=3)
    assert "t-exec-missing" not in ALGORITHMS and "t-exec-fx3" not in ALGORITHMS


def test_an_executable_spec_pickles_by_reference_for_the_workers():
    hull = ExecutableHull.from_command(_planted("ok"), dim=2, output="Fx")
    assert pickle.loads(pickle.dumps(hull)) == hull


def test_points_the_format_cannot_carry_are_not_given_to_the_program():
    spec = register_executable("t-exec-shapes", _planted("ok"), dim=2, output="Fx")
    try:
        config = AlgorithmConfig(spec.name)
        three_d = evaluate(Case.from_points(np.ones((5, 3)), dim=2, family="t"), config, qhull=False)
        one_point = evaluate(Case.from_points([[1.0, 2.0]]), config, qhull=False)
        assert three_d.status == one_point.status == "rejected"
        assert "not 2D points" in three_d["reason"]
        assert "cannot say 1 points in 2D" in one_point["reason"]
    finally:
        ALGORITHMS.remove(spec.name)


# -- the planted-bug program through the command line ------------------------------------

PLANTED_EXPECTED = {
    # mode: (status, column, text in it)
    "ok": ("pass", "reason", ""),
    "segv": ("crash", "reason", "killed by signal 11 (SIGSEGV)"),
    "hang": ("timeout", "reason", "exceeded 2.0 s"),
    "garbage": ("fail", "reason", "output contract: unreadable output at line 1 'hello, hull'"),
    "drop": ("fail", "failed_checks", "containment"),
    "range": ("fail", "reason", "line 6 '7': index 7 is out of range for 7 points"),
    "clockwise": ("fail", "failed_checks", "manifoldness"),
    "exit": ("error", "reason", "exited with code 3; stderr: boom: cannot hull this"),
    "chatty": ("pass", "reason", ""),
}


def test_planted_bugs_get_their_statuses(tmp_path, square_file):
    args = ["run", "--points-file", str(square_file), "--sphere", "off", "--workers", "2", "--timeout", "2",
            "--no-shrink", "--no-qhull", "--out", str(tmp_path / "out")]
    for mode in PLANTED_EXPECTED:
        args += ["--exec", f"planted-{mode}[dim=2,output=Fx]={_planted(mode)}", "--algorithm", f"planted-{mode}"]
    pid_file = tmp_path / "hang.pid"
    res = run_cli(*args, env={"PLANTED_PID_FILE": str(pid_file)})
    assert res.returncode == 1, res.stderr
    table = pd.read_csv(_run_dir(res.stdout) / "results.csv", keep_default_na=False).set_index("algorithm")
    assert set(table["origin"]) == {"executable"}
    for mode, (status, column, text) in PLANTED_EXPECTED.items():
        row = table.loc[f"planted-{mode}"]
        assert row["status"] == status, (mode, row["reason"])
        assert text in row[column], (mode, row[column])
    # The program's own stderr is in its row, never on the terminal.
    assert "chatty hull program at work" in table.loc["planted-chatty", "call_output"]
    assert "boom" in table.loc["planted-exit", "call_output"]
    assert "chatty hull program" not in res.stdout + res.stderr and "boom" not in res.stderr
    # The hung program died with its worker.
    pid = int(pid_file.read_text())
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline and alive(pid):
        time.sleep(0.1)
    assert not alive(pid)
    # The reproduce commands re-register the program.
    failures = _run_dir(res.stdout) / "failures"
    index = json.loads((failures / "index.json").read_text())
    slug = next(entry["slug"] for entry in index["folders"] if entry["algorithm"] == "planted-drop")
    recorded = json.loads((failures / slug / "case.json").read_text())["registration"]
    assert "--exec" in recorded and any("planted_hull.py drop" in arg for arg in recorded)


def test_a_clockwise_program_gets_a_hint_and_passes_with_clockwise(tmp_path, square_file, capsys):
    other = tmp_path / "other.txt"
    other.write_text(format_points(SQUARE * 3.0 + 1.0))
    args = ["run", "--points-file", str(square_file), "--points-file", str(other), "--sphere", "off",
            "--workers", "0", "--no-shrink", "--out", str(tmp_path / "out"),
            "--exec", f"cw[dim=2,output=Fx]={_planted('clockwise')}", "--algorithm", "cw"]
    assert main(args) == 1
    err = capsys.readouterr().err
    assert "hint: every hull cw returned (2 checked) is clockwise" in err and "--clockwise cw" in err
    assert main(args + ["--clockwise", "cw"]) == 0
    assert "hint:" not in capsys.readouterr().err
    assert "cw" not in ALGORITHMS  # the command's programs do not outlive it


# -- the real Qhull -----------------------------------------------------------------------

#: Families where scipy's Qhull and qconvex face the same input and the same Qhull code.
#: (``bad-input`` is left out on purpose: there the wrappers differ, not Qhull: scipy refuses
#: NaN in Python and crashes on 3-axis arrays, while qconvex reads "nan" and hulls it.)
QHULL_FAMILIES = ("uniform", "sphere", "cube-faces", "coplanar-grid", "collinear-line", "duplicates",
                  "lattice-block", "near-coplanar", "pinched", "narrow-cone", "scaled", "kettner-classroom",
                  "regular-polygon", "minkowski-cubes")


def test_qconvex_through_exec_gets_scipys_verdicts(tmp_path, qhull_programs):
    qconvex = qhull_programs["qconvex"]
    args = ["run", "--sphere", "off", "--sizes", "16", "--seed", "7", "--no-shrink", "--no-qhull",
            "--out", str(tmp_path / "out"), "--quiet",
            # scipy runs Qhull with Qt (triangles); Qhull's 3D 'i' facets are clockwise seen from outside.
            "--exec", f"qconvex={qconvex} Qt i", "--clockwise", "qconvex",
            "--exec", f"qconvex-2d[dim=2,output=Fx]={qconvex} Fx",
            "--algorithm", "qconvex", "--algorithm", "qconvex-2d",
            "--algorithm", "scipy-qhull-3d", "--algorithm", "scipy-qhull-2d",
            "--generator", "rbox:40 D3 s W1e-13", "--generator", "rbox:30 D2 M3,4 z"]
    args += [f"--generator={family}" for family in QHULL_FAMILIES]
    res = run_cli(*args)
    assert res.returncode in (0, 1), res.stderr
    table = pd.read_csv(_run_dir(res.stdout) / "results.csv", keep_default_na=False)
    ours = table[table["origin"] == "executable"].set_index("case_id")["status"]
    scipys = table[table["origin"] == "adapter"].set_index("case_id")["status"]
    assert len(ours) == len(scipys) >= 100
    both = pd.DataFrame({"qconvex": ours, "scipy": scipys.reindex(ours.index)})
    differ = both[both["qconvex"] != both["scipy"]]
    assert differ.empty, table.set_index("case_id").loc[differ.index, ["generator", "params", "algorithm",
                                                                        "status", "reason"]].to_string()
    # A sweep that only passed would prove little: Qhull declines flat inputs and fails inexact ones.
    assert {"pass", "rejected", "fail"} <= set(ours)
    assert "rbox" in set(table["generator"])


def test_check_and_export_speak_qhull(tmp_path, qhull_programs, capsys, monkeypatch):
    def program(*argv, stdin=None):
        return subprocess.run(argv, input=stdin, capture_output=True, text=True, check=True).stdout

    points = tmp_path / "points.txt"
    points.write_text(program(qhull_programs["rbox"], "30", "D3", "t3"))
    (tmp_path / "hull.i").write_text(program(qhull_programs["qconvex"], "i", stdin=points.read_text()))
    assert main(["check", str(points), str(tmp_path / "hull.i"), "--clockwise"]) == 0
    assert main(["check", str(points), str(tmp_path / "hull.i")]) == 1  # Qhull's 3D 'i' is clockwise
    capsys.readouterr()
    assert main(["export", str(points), "--format", "i", "-o", str(tmp_path / "ours.i")]) == 0
    assert main(["check", str(points), str(tmp_path / "ours.i"), "--clockwise", "--faces-format", "i"]) == 0
    flat = tmp_path / "flat.txt"
    flat.write_text(program(qhull_programs["rbox"], "20", "D2", "t5"))
    fx = program(qhull_programs["qconvex"], "Fx", stdin=flat.read_text())
    monkeypatch.setattr(sys, "stdin", io.StringIO(fx))
    assert main(["check", str(flat), "-"]) == 0  # Fx's count line is not taken for an index
    capsys.readouterr()
    assert main(["export", str(flat), "--format", "Fx"]) == 0
    assert sorted(capsys.readouterr().out.split()[1:]) == sorted(fx.split()[1:])


def test_readme_exec_example_runs_as_printed(tmp_path, qhull_programs):
    """The README's third way in: Qhull's qconvex through --exec, exactly as printed there."""
    import re

    readme = (Path(__file__).resolve().parents[1] / "README.md").read_text(encoding="utf-8")
    command = re.search(r"<!-- exec-command -->\s*```\n(.*?)```", readme, re.S).group(1).strip()
    path = os.pathsep.join([str(Path(qhull_programs["qconvex"]).parent), str(Path(PY).parent),
                            os.environ.get("PATH", "")])
    res = subprocess.run(command, shell=True, cwd=tmp_path, capture_output=True, text=True, timeout=600,
                         env={**os.environ, "PATH": path})
    assert res.returncode in (0, 1), res.stderr
    table = pd.read_csv(tmp_path / _run_dir(res.stdout) / "results.csv", keep_default_na=False)
    assert set(table["algorithm"]) == {"qconvex"} and set(table["origin"]) == {"executable"}
    uniform = table[(table["generator"] == "uniform") & (table["sphere"] == "off")]
    assert len(uniform) > 0 and set(uniform["status"]) == {"pass"}


def test_rbox_cases_are_seeded_from_the_run(qhull_programs):
    from hullstress.sweep import SweepOptions, build_cases

    def cases(seed):
        return build_cases(SweepOptions(generators=("rbox:25 D3 s",), seed=seed))[0]

    a, b, c = cases(1), cases(1), cases(2)
    assert len(a) == 1 and a[0].family == "rbox" and a[0].dim == 3 and a[0].n_points == 25
    assert a[0].case_id == b[0].case_id and np.array_equal(a[0].points, b[0].points)
    assert a[0].case_id != c[0].case_id
    assert a[0].source.startswith("rbox 25 D3 s t")
    assert np.allclose(np.linalg.norm(a[0].points, axis=1), 0.5)  # rbox s: on a sphere of radius 0.5


def test_points_from_stdin(tmp_path, qhull_programs, capsys, monkeypatch):
    rbox = subprocess.run([qhull_programs["rbox"], "20", "D2", "t9"], capture_output=True, text=True, check=True)
    monkeypatch.setattr(sys, "stdin", io.StringIO(rbox.stdout))
    code = main(["run", "--points-file", "-", "--algorithm", "monotone-chain", "--sphere", "off", "--eps", "scaled",
                 "--workers", "0", "--no-shrink", "--out", str(tmp_path)])
    assert code == 0, capsys.readouterr().err
    table = pd.read_csv(_run_dir(capsys.readouterr().out) / "results.csv", keep_default_na=False)
    assert table["n_points"].tolist() == [20] and table["status"].tolist() == ["pass"]
