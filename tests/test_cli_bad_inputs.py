"""Every bad input, for every subcommand: the documented exit status and one line naming the value.

One table (``BAD_INPUTS``) of command lines, each with the exit status it
must end with (2 usage or input error, 4 environment failure, 5 no work done)
and a fragment of the one line it must print on stderr; no traceback, ever.
Placeholders in the command lines name files made once for the table
(``{square}``, ``{plugin_a}``, ...); ``{tmp}`` is the case's own folder.

A full disk is simulated separately, in a subprocess with a file-size limit.
"""

from __future__ import annotations

import io
import json
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

from hullstress._registry import ALGORITHMS, GENERATORS
from hullstress.cli import EXIT_ENVIRONMENT, EXIT_NO_WORK, EXIT_USAGE, main

PLANTED = Path(__file__).resolve().parent / "programs" / "planted_hull.py"
U, E, N = EXIT_USAGE, EXIT_ENVIRONMENT, EXIT_NO_WORK

#: Files the table refers to, by placeholder name: content (str), or a callable writing it.
FILES = {
    "square": "0,0\n1,0\n1,1\n0,1\n",
    "cube": "0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 1 1\n",
    "square_faces": "4\n0\n1\n2\n3\n",
    "letters_faces": "0 1 x\n",
    "range_faces": "0 1 9\n",
    "bad_csv": "x,y\n1,2\n3,oops\n",
    "ragged": "0 0 0\n1 1\n",
    "empty": "",
    "four_d": "0,0,0,0\n1,1,1,1\n",
    "nan": "0,0\n1,nan\n0,1\n",
    "header_mismatch": "2\n5\n0 0\n1 0\n0 1\n",
    "not_results": "hello\n",
    "a_file": "I am a file, not a folder\n",
    "a_results_table": "case_id,algorithm,sphere,eps,generator,dim,status\nc0,monotone-chain,off,scaled,uniform,2,pass\n",
    "corrupt_corpus": '{"format": "hullstress-corpus", "id": 5}\n',
    "plugin_a": "from hullstress import register_algorithm\n\n@register_algorithm('dup-name', dim=2)\n"
                "def first(points):\n    return [0, 1, 2]\n",
    "plugin_b": "from hullstress import register_algorithm\n\n@register_algorithm('dup-name', dim=2)\n"
                "def second(points):\n    return [0, 1, 2]\n",
    "plugin_builtin": "from hullstress import register_algorithm\n\n@register_algorithm('monotone-chain', dim=2)\n"
                      "def mine(points):\n    return [0, 1, 2]\n",
    "plugin_dim4": "from hullstress import register_algorithm\n\n@register_algorithm('four-d', dim=4)\n"
                   "def mine(points):\n    return [0, 1, 2]\n",
    "plugin_syntax": "def broken(:\n",
    "plugin_raises": "raise RuntimeError('no licence server')\n",
    "plugin_txt": "not python at all\n",
}
FOLDERS = ("empty_dir", "corpus_one_bad")

# (command line, exit status, fragment of the one stderr line)
BAD_INPUTS = [
    # -- numbers -------------------------------------------------------------------------
    ("run --timeout 1e309", U, "argument --timeout: must be a finite number, got '1e309'"),
    ("run --timeout inf", U, "argument --timeout: must be a finite number, got 'inf'"),
    ("run --timeout nan", U, "argument --timeout: must be a finite number, got 'nan'"),
    ("run --timeout 0", U, "argument --timeout: must be a positive number of seconds, got '0'"),
    ("run --timeout -1", U, "argument --timeout: must be a positive number of seconds, got '-1'"),
    ("run --timeout soon", U, "argument --timeout: expected a number, got 'soon'"),
    ("run --time-budget 0", U, "argument --time-budget: must be a positive number of seconds, got '0'"),
    ("run --time-budget -5", U, "argument --time-budget: must be a positive number of seconds, got '-5'"),
    ("run --time-budget 1e999", U, "argument --time-budget: must be a finite number, got '1e999'"),
    ("run --memory-limit inf", U, "argument --memory-limit: must be a finite number, got 'inf'"),
    ("run --memory-limit -1", U, "argument --memory-limit: must be 0 (no limit) or a positive number of MiB, got '-1'"),
    ("run --memory-limit nan", U, "argument --memory-limit: must be a finite number, got 'nan'"),
    ("run --memory-limit lots", U, "argument --memory-limit: expected a number, got 'lots'"),
    ("run --memory-limit 1", U, "argument --memory-limit: '1' MiB is below the minimum of 64 MiB"),
    ("search --memory-limit 0.5", U, "argument --memory-limit: '0.5' MiB is below the minimum of 64 MiB"),
    ("report {tmp}/no-such-run", U, "no-such-run': no such folder"),
    ("report {tmp}", U, "is not a run folder: it has no run.json"),
    ("report", U, "the following arguments are required: RUN_FOLDER"),
    ("run --workers -1", U, "argument --workers: must be at least 0, got '-1'"),
    ("run --workers 1.5", U, "argument --workers: expected an integer, got '1.5'"),
    ("run --workers two", U, "argument --workers: expected an integer, got 'two'"),
    ("run --seed abc", U, "argument --seed: invalid int value: 'abc'"),
    ("run --seed 1.5", U, "argument --seed: invalid int value: '1.5'"),
    ("run --sizes 1e8 --algorithm monotone-chain", U,
     "--sizes 100000000: a case of 100000000 2D points needs about"),
    ("run --sizes 2000000 --memory-limit 100 --algorithm kenwright", U, "more than the --memory-limit of 100 MiB"),
    ("run --sizes 1000000000000 --memory-limit 0", U, "of memory; use smaller sizes or a larger --memory-limit"),
    ("run --sizes 0", U, "--sizes must be positive, got 0 in '0'"),
    ("run --sizes ten", U, "--sizes must be comma-separated positive integers, got 'ten'"),
    ("run --sizes 10,-3", U, "--sizes must be positive, got -3 in '10,-3'"),
    ("run --sizes 2.5", U, "got '2.5' in '2.5'"),
    ("run --sizes 1e400", U, "got '1e400' in '1e400'"),
    ("run --sizes ,", U, "--sizes must be comma-separated positive integers, got ','"),
    ("run --generator rbox:1e9 --algorithm kenwright", U, "--generator 'rbox:1e9'"),
    ("replay {empty_dir} --workers -1", U, "argument --workers: must be at least 0, got '-1'"),
    ("replay {empty_dir} --timeout 0", U, "argument --timeout: must be a positive number of seconds, got '0'"),
    ("replay {empty_dir} --timeout inf", U, "argument --timeout: must be a finite number, got 'inf'"),
    ("shrink {square} --algorithm monotone-chain --budget 0", U, "argument --budget: must be a positive number"),
    ("shrink {square} --algorithm monotone-chain --budget inf", U, "argument --budget: must be a finite number"),
    ("shrink {square} --algorithm monotone-chain --max-calls 0", U, "argument --max-calls: must be at least 1, got '0'"),
    ("shrink {square} --algorithm monotone-chain --timeout -1", U, "argument --timeout: must be a positive number"),
    ("fuzz --algorithm monotone-chain --max-examples 0", U, "argument --max-examples: must be at least 1, got '0'"),
    ("fuzz --algorithm monotone-chain --max-findings 0", U, "argument --max-findings: must be at least 1, got '0'"),
    ("search --evaluations 0", U, "argument --evaluations: must be at least 1, got '0'"),
    ("search --algorithm no-such-hull", U, "no-such-hull"),
    ("fuzz --algorithm monotone-chain --max-size 2", U, "argument --max-size: must be at least 4, got '2'"),
    ("fuzz --algorithm monotone-chain --shrink-budget -1", U, "argument --shrink-budget: must be 0 or more seconds"),
    ("fuzz --algorithm monotone-chain --timeout nan", U, "argument --timeout: must be a finite number, got 'nan'"),
    ("fuzz --algorithm monotone-chain --seed x", U, "argument --seed: invalid int value: 'x'"),
    ("check {square} {square_faces} --max-offending -1", U, "argument --max-offending: must be at least 0, got '-1'"),
    ("check {square} {square_faces} --dim 4", U, "argument --dim: invalid choice: 4"),
    # -- names ---------------------------------------------------------------------------
    ("run --algorithm no-such-hull", U, "unknown algorithm 'no-such-hull'; valid names: "),
    ("run --generator no-such-family", U, "unknown generator 'no-such-family'; valid names: "),
    ("run --profile weekly", U, "invalid choice: 'weekly'"),
    ("run --sphere maybe", U, "argument --sphere: invalid choice: 'maybe'"),
    ("run --eps tiny", U, "argument --eps: invalid choice: 'tiny'"),
    ("run --clockwise no-such-hull", U, "unknown algorithm 'no-such-hull'; valid names: "),
    ("run --qhull-options nonsense", U, "--qhull-options 'nonsense': Qhull refused them"),
    ("run --generator 'rbox:100 t5'", U, "leave out rbox's seed option 't5'"),
    ("run --generator 'rbox:100 D4' --algorithm kenwright", U, "wrong dimension: the header gives 4"),
    ("run --generator \"rbox:100 'unclosed\"", U, "--generator \"rbox:100 'unclosed\": No closing quotation"),
    ("run --generator rbox:fish", U, "--generator 'rbox:fish': rbox exited with code"),
    ("list everything", U, "argument what: invalid choice: 'everything'"),
    ("shrink {square} --algorithm nope", U, "unknown algorithm 'nope'; valid names: "),
    ("shrink {square} --algorithm monotone-chain --check nonsense", U,
     "--check 'nonsense' is not a failure hullstress knows; valid checks: contract, convexity, containment"),
    ("shrink {square} --algorithm monotone-chain --sphere sideways", U, "argument --sphere: invalid choice"),
    ("fuzz --algorithm nope", U, "unknown algorithm 'nope'; valid names: "),
    ("fuzz --algorithm monotone-chain --generator nope", U, "unknown generator 'nope'"),
    ("fuzz --algorithm monotone-chain --eps huge", U, "argument --eps: invalid choice: 'huge'"),
    ("replay {empty_dir} --algorithm nope", U, "unknown algorithm 'nope'; valid names: "),
    ("export {square} --format pdf", U, "argument --format: invalid choice: 'pdf'"),
    ("export {square}", U, "the following arguments are required: --format"),
    ("check {square} {square_faces} --faces-format stl", U, "argument --faces-format: invalid choice: 'stl'"),
    ("check {square} {square_faces} --qhull-options nonsense", U, "--qhull-options 'nonsense': Qhull refused them"),
    ("run --unknown-option", U, "unrecognized arguments: --unknown-option"),
    ("run stray-argument", U, "unrecognized arguments: stray-argument"),
    ("", U, "the following arguments are required: COMMAND"),
    ("frobnicate", U, "argument COMMAND: invalid choice: 'frobnicate'"),
    # -- programs (--exec) ---------------------------------------------------------------
    ("run --exec qhull", U, "--exec 'qhull': expected NAME=COMMAND"),
    ("run --exec =qconvex", U, "--exec '=qconvex': expected NAME=COMMAND"),
    ("run --exec q=", U, "--exec 'q=': expected NAME=COMMAND"),
    ("run --exec q=no-such-hull-program-xyz", U, "program 'no-such-hull-program-xyz' not found on PATH"),
    ("run --exec 'q[dim=4]=sh'", U, "--exec 'q[dim=4]=sh': dim must be one of 2, 3, got '4'"),
    ("run --exec 'q[output=o]=sh'", U, "output must be one of i, Fx, off, got 'o'"),
    ("run --exec 'q[colour=red]=sh'", U, "unknown option 'colour'"),
    ("run --exec 'q[output=Fx]=sh'", U, "output 'Fx' lists extreme points, a hull only in 2D"),
    ("run --exec \"q=sh 'unbalanced\"", U, "No closing quotation"),
    ("run --exec monotone-chain=sh", U, "algorithm 'monotone-chain' is already registered by"),
    ("run --exec q=sh --exec 'q=sh -c true'", U, "algorithm 'q' is already registered by the program 'sh'"),
    ("list --exec q=no-such-hull-program-xyz", U, "program 'no-such-hull-program-xyz' not found on PATH"),
    ("shrink {square} --algorithm q --exec q=no-such-hull-program-xyz", U, "not found on PATH"),
    # -- plug-ins ------------------------------------------------------------------------
    ("run --plugin /nonexistent/plugin.py", U, "--plugin '/nonexistent/plugin.py': no such file"),
    ("run --plugin no_such_module_xyz", U, "--plugin 'no_such_module_xyz': no module named 'no_such_module_xyz'"),
    ("run --plugin {plugin_syntax}", U, "import failed: SyntaxError"),
    ("run --plugin {plugin_raises}", U, "import failed: RuntimeError: no licence server"),
    ("run --plugin {plugin_a} --plugin {plugin_b}", U, "algorithm 'dup-name' is already registered by"),
    ("run --plugin {plugin_builtin}", U, "algorithm 'monotone-chain' is already registered by"),
    ("run --plugin {plugin_dim4}", U, "dim must be 2 or 3, got 4"),
    ("run --plugin {plugin_txt}", U, "not an importable Python file"),
    ("list --plugin /nonexistent/plugin.py", U, "--plugin '/nonexistent/plugin.py': no such file"),
    ("replay {empty_dir} --plugin {plugin_raises}", U, "import failed: RuntimeError: no licence server"),
    # -- files and folders ---------------------------------------------------------------
    ("run --points-file /nonexistent/points.csv", U, "points file '/nonexistent/points.csv' does not exist"),
    ("run --points-file {bad_csv}", U, "non-numeric token 'oops' at line 3"),
    ("run --points-file {ragged}", U, "ragged rows: line 2 has 2 values, expected 3"),
    ("run --points-file {empty}", U, "is empty"),
    ("run --points-file {four_d}", U, "wrong dimension: expected 2 or 3 coordinates per point, got 4"),
    ("run --points-file {nan}", U, "nan.csv': point 1 at line 2 has a non-finite coordinate"),
    ("run --points-file {empty_dir}", U, "is a directory, expected a file"),
    ("run --points-file {header_mismatch}", U, "the header announces 5 points, the file has 3"),
    ("run --points-file -", U, "points file '-' is empty"),
    ("run --points-file - <<junk junk\nmore junk", U, "points file '-'"),
    ("run --points-file {cube} --algorithm monotone-chain", U, "nothing to run: no case matches"),
    ("run --generator spiral --algorithm monotone-chain", U, "nothing to run: no case matches"),
    ("run --baseline /nonexistent/run", U, "--baseline '/nonexistent/run': no such file or directory"),
    ("run --baseline {not_results}", U, "--baseline"),
    ("run --last-failed --failed-first", U, "argument --failed-first/--ff: not allowed with argument --last-failed"),
    ("run --out {a_file}/sub --points-file {square}", U, "--out '{a_file}/sub': cannot write there"),
    ("run --out /sys/hullstress-test-out --points-file {square}", E, "--out '/sys/hullstress-test-out': cannot write there"),
    ("run --junit /sys/hullstress-junit.xml --points-file {square}", E,
     "--junit '/sys': cannot write there"),
    ("run --junit {empty_dir} --points-file {square}", U, "is a folder, expected a file name"),
    ("run --save-corpus /sys/hullstress-corpus --points-file {square}", E,
     "--save-corpus '/sys/hullstress-corpus': cannot write there"),
    ("run --save-corpus {a_file} --points-file {square}", U, "--save-corpus '{a_file}': cannot write there"),
    ("reproduce /nonexistent/failure-folder", U, "reproduce: '/nonexistent/failure-folder' is not a folder"),
    ("reproduce {empty_dir}", U, "is not a failure folder (no case.json)"),
    ("reproduce {empty_dir} --timeout -1", U, "argument --timeout: must be a positive number of seconds, got '-1'"),
    ("findings /nonexistent/run", U, "RUN '/nonexistent/run': no such file or directory"),
    ("findings {empty_dir}", U, "no results table in this folder (expected results.parquet or results.csv)"),
    ("findings {not_results}", U, "cannot read the results table"),
    ("findings {a_results_table} --out {a_file}", U, "--out '{a_file}': cannot write the findings there"),
    ("findings {a_results_table} --out /sys/hullstress-findings", E,
     "--out '/sys/hullstress-findings': cannot write the findings there"),
    ("check /nonexistent/points.csv {square_faces}", U, "points file '/nonexistent/points.csv' does not exist"),
    ("check {square} /nonexistent/faces.txt", U, "faces file '/nonexistent/faces.txt' does not exist"),
    ("check {square} {letters_faces}", U, "non-integer token 'x' at line 1"),
    ("check {square} {range_faces}", U, "holds index 9, out of range for 4 points"),
    ("check {square} {square_faces} --dim 3", U, "wrong dimension: expected 3 coordinates per point, got 2"),
    ("check - -", U, "POINTS and FACES cannot both be '-'"),
    ("check {square} {letters_faces} --faces-format i", U, "line 1 '0 1 x': expected the number of facets"),
    ("check {square} {square_faces} --faces-format off", U, "expected 'OFF'"),
    ("export /nonexistent/case.json --format csv", U, "CASE '/nonexistent/case.json': no such file"),
    ("export no-such-entry --format csv --corpus {empty_dir}", U, "no entry 'no-such-entry' in corpus"),
    ("export {square} --format npy", U, "--format npy writes binary: give -o FILE"),
    ("export {square} --format off", U, "--format off needs 3D points"),
    ("export {corrupt_corpus} --format csv", U, "corrupt_corpus"),
    ("export {square} --format qhull -o /sys/hullstress-export.txt", E,
     "cannot write '/sys/hullstress-export.txt': Permission denied"),
    ("export {square} --format qhull -o /dev/full", E, "cannot write '/dev/full': No space left on device"),
    ("export {square} --format csv -o {empty_dir}", U, "is a folder, expected a file name"),
    ("export {square} --format csv -o /nonexistent/dir/out.csv", U, "no such folder '/nonexistent/dir'"),
    ("replay /nonexistent/corpus", U, "corpus '/nonexistent/corpus': no such file or directory"),
    ("replay {empty_dir}", N, "no work done: nothing to replay"),
    ("replay {corpus_one_bad}", U, "corpus_one_bad"),
    ("shrink /nonexistent/points.csv --algorithm monotone-chain", U, "does not exist"),
    ("shrink {square} --algorithm monotone-chain --dim 3", U,
     "--dim 3 does not match algorithm 'monotone-chain', which takes 2D points"),
    ("shrink {square} --algorithm monotone-chain --raw", U, "--raw needs a .npy points file"),
    ("shrink {square} --algorithm kenwright", U, "wrong dimension: expected 3 coordinates per point, got 2"),
]


def _ids() -> list[str]:
    return [argv[:70] or "(nothing)" for argv, _, _ in BAD_INPUTS]


@pytest.fixture(scope="module")
def files(tmp_path_factory) -> dict[str, str]:
    root = tmp_path_factory.mktemp("bad-inputs")
    paths = {}
    for name, content in FILES.items():
        suffix = ".py" if name.startswith("plugin") and name != "plugin_txt" else (
            ".csv" if name in ("square", "bad_csv", "four_d", "nan") else ".txt")
        if name == "corrupt_corpus":
            suffix = ".json"
        path = root / f"{name}{suffix}"
        path.write_text(content)
        paths[name] = str(path)
    for name in FOLDERS:
        (root / name).mkdir()
        paths[name] = str(root / name)
    (root / "corpus_one_bad" / "broken.json").write_text("{not json")
    return paths


@pytest.fixture
def clean_registry():
    """Names and plug-in modules a command registers are forgotten after it (the table runs in one process)."""
    algorithms, generators = set(ALGORITHMS.names()), set(GENERATORS.names())
    modules = set(sys.modules)
    yield
    for name in set(ALGORITHMS.names()) - algorithms:
        ALGORITHMS.remove(name)
    for name in set(GENERATORS.names()) - generators:
        GENERATORS.remove(name)
    for name in set(sys.modules) - modules:
        if name.startswith("hullstress_plugin_"):
            del sys.modules[name]


@pytest.mark.parametrize("command, status, fragment", BAD_INPUTS, ids=_ids())
def test_bad_input_exit_status_and_one_line(command, status, fragment, files, tmp_path, monkeypatch, capsys,
                                            clean_registry):
    import shlex

    command, _, stdin = command.partition(" <<")
    values = {**files, "tmp": str(tmp_path)}
    argv = [arg.format(**values) for arg in shlex.split(command)]
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(sys, "stdin", io.StringIO(stdin))
    code = main(argv)
    err = capsys.readouterr().err
    lines = [line for line in err.splitlines() if line.strip()]
    assert code == status, err
    assert len(lines) == 1, err
    assert fragment.format(**values) in lines[0]
    assert "Traceback" not in err and "internal error" not in err


def test_the_table_covers_every_subcommand_and_status():
    from hullstress.cli import SUBCOMMANDS

    commands = {argv.split()[0] for argv, _, _ in BAD_INPUTS if argv}
    assert set(SUBCOMMANDS) <= commands
    assert {U, E, N} == {status for _, status, _ in BAD_INPUTS}
    assert len(BAD_INPUTS) >= 127


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="the full disk is a file-size limit (RLIMIT_FSIZE)")
def test_a_full_disk_keeps_what_was_written_and_exits_4(tmp_path):
    """The run folder's disk fills up mid-sweep: one line naming the file, exit 4, the rows written stay."""
    points = tmp_path / "points"
    points.mkdir()
    args = []
    for k in range(12):
        path = points / f"p{k}.csv"
        np.savetxt(path, np.random.default_rng(k).random((6, 2)), delimiter=",")
        args += ["--points-file", str(path)]
    limit = textwrap.dedent("""
        import resource, signal, sys
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)   # a write past the limit fails with EFBIG, like ENOSPC
        resource.setrlimit(resource.RLIMIT_FSIZE, (12000, 12000))
        from hullstress.cli import console_main
        sys.argv[0] = "hullstress"
        console_main()
    """)
    res = subprocess.run([sys.executable, "-c", limit, "run", *args, "--algorithm", "monotone-chain",
                          "--workers", "1", "--no-qhull", "--quiet", "--out", str(tmp_path / "out")],
                         capture_output=True, text=True, timeout=300)
    lines = [line for line in res.stderr.splitlines() if line.strip()]
    assert res.returncode == EXIT_ENVIRONMENT, res.stderr
    assert len(lines) == 1 and "Traceback" not in res.stderr
    assert "hullstress: error: cannot write" in lines[0] and "File too large" in lines[0]
    run_dir = next((tmp_path / "out").iterdir())
    assert str(run_dir) in lines[0]
    partial = run_dir / "results.partial.csv"
    assert partial.is_file() and len(partial.read_text().splitlines()) > 2  # the rows written before stay
    meta = json.loads((run_dir / "run.json").read_text())
    assert meta["state"] == "environment-failure" and meta["environment_errors"]
