"""The documentation cannot drift from the code: the site builds strictly, every option is documented,
and the command blocks a user pastes from the README and the docs run as printed.

Command blocks.  A fenced block in README.md or a page of the site's nav that has no language (or
``bash``/``sh``/``shell``/``console``) is a command a user pastes.  Each one carries a tag on the line
before it: ``<!-- journey: NAME -->``, or one of the README's own tags (``<!-- run-command -->``,
``<!-- plugin-command -->``, ...), and :data:`JOURNEYS` says how the test runs it.  An untagged command
block fails :func:`test_every_command_block_is_tagged_and_known`; a block that is not a command to
paste (a synopsis, an output sample) is marked ``text``.  Where a command as printed is long (the whole
quick profile, a nightly run), the fast test substitutes a documented smaller option set and says which
(:attr:`Journey.smaller`); the command exactly as printed runs in the slow (nightly) profile.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import shutil
import socket
import subprocess
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import pandas as pd
import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
README = ROOT / "README.md"
PY_BIN = Path(sys.executable).parent

#: Tags the README used before the journeys had a tag of their own; they stay, because other tests
#: and .ci/run read them.
README_TAGS = ("run-command", "test-command", "plugin-example", "plugin-command", "exec-command")
TAG = re.compile(r"<!-- (?:journey: )?([a-z0-9-]+) -->[ \t]*\n```([a-z]*)\n(.*?)```", re.S)
FENCE = re.compile(r"^```([a-z]*)\n(.*?)^```", re.S | re.M)
COMMAND_LANGUAGES = ("", "bash", "sh", "shell", "console")


def _nav_pages() -> list[Path]:
    """The pages of mkdocs.yml's nav (a page enters the checks when it enters the site's navigation)."""
    text = (ROOT / "mkdocs.yml").read_text(encoding="utf-8")
    nav = text.split("\nnav:", 1)[1]
    return [DOCS / name for name in re.findall(r":\s*([\w./-]+\.md)\s*$", nav, re.M)]


def _documents() -> list[Path]:
    return [README, *_nav_pages()]


def _tagged_blocks() -> dict[str, list[tuple[Path, str, str]]]:
    """Every tagged block: tag -> [(file, language, text)]."""
    found: dict[str, list[tuple[Path, str, str]]] = {}
    for path in _documents():
        for m in TAG.finditer(path.read_text(encoding="utf-8")):
            found.setdefault(m.group(1), []).append((path, m.group(2), m.group(3)))
    return found


def block(tag: str) -> str:
    """The text of the block tagged ``tag`` (the same in every document that carries it)."""
    blocks = _tagged_blocks()[tag]
    texts = {text for _, _, text in blocks}
    assert len(texts) == 1, f"the blocks tagged {tag} differ between {[str(p) for p, _, _ in blocks]}"
    return texts.pop()


# -- the site --------------------------------------------------------------------------------------------


def test_mkdocs_build_is_strict_and_clean(tmp_path):
    pytest.importorskip("mkdocs", reason="mkdocs is not installed: pip install -e '.[docs]'")
    pytest.importorskip("material", reason="mkdocs-material is not installed: pip install -e '.[docs]'")
    env = {**os.environ, "NO_MKDOCS_2_WARNING": "1"}
    res = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "--config-file",
                          str(ROOT / "mkdocs.yml"), "--site-dir", str(tmp_path / "site")],
                         capture_output=True, text=True, env=env, timeout=300)
    assert res.returncode == 0, res.stderr[-4000:]
    home = (tmp_path / "site" / "index.html").read_text(encoding="utf-8")
    assert "hullstress" in home and "own-code.html" in home
    # The figures the benchmarks wrote are in the performance page, not shown as an include line.
    performance = (tmp_path / "site" / "performance.html").read_text(encoding="utf-8")
    assert "--8&lt;--" not in performance and "Written by benchmarks/bench_runner.py" in performance


def test_figure_includes_name_existing_files_written_by_a_benchmark():
    includes = {name for page in DOCS.glob("*.md")
                for name in re.findall(r'^--8<-- "([^"]+)"$', page.read_text(encoding="utf-8"), re.M)}
    assert includes, "no page includes a figure file"
    for name in includes:
        path = DOCS / name
        assert path.is_file(), name
        bench = re.match(r"figures/(bench_\w+)\.md$", name)
        assert bench and (ROOT / "benchmarks" / f"{bench.group(1)}.py").is_file(), name
        assert path.read_text(encoding="utf-8").startswith(f"<!-- Written by benchmarks/{bench.group(1)}.py")


def test_readme_is_a_short_front_door():
    text = README.read_text(encoding="utf-8")
    assert len(text.splitlines()) <= 300
    first_screen = "\n".join(text.splitlines()[:20])
    assert "(#testing-your-own-hull-code)" in first_screen and "(docs/index.md)" in first_screen
    # Every page the README links to exists.
    for target in re.findall(r"\]\((docs/[^)#]+)", text):
        assert (ROOT / target).is_file(), target


def test_the_docs_quick_start_is_the_readme_s():
    index = (DOCS / "index.md").read_text(encoding="utf-8")
    for tag in ("run-command", "test-command"):
        assert block(tag).strip() in index


#: The team's background design notes, which a clone of the repository does not contain (spelled in two
#: pieces so that this file does not cite it).
OUTSIDE_NOTES = "DESIGN" ".md"


def test_no_code_cites_a_file_outside_the_repository():
    cited = []
    for folder in ("hullstress", "generators", "tests", "tools", "benchmarks"):
        for path in (ROOT / folder).rglob("*.py"):
            text = path.read_text(encoding="utf-8")
            if OUTSIDE_NOTES in text:
                cited.append(str(path.relative_to(ROOT)))
            for page in re.findall(r"docs/([\w-]+\.md)", text):
                assert (DOCS / page).is_file() or page in FUTURE_PAGES, f"{path}: docs/{page} does not exist"
    assert not cited, f"these cite {OUTSIDE_NOTES}, which the repository does not contain: {cited}"


#: Pages other branches are writing (docs/ is shared); a docstring may cite them before they land here.
FUTURE_PAGES: set[str] = set()


# -- every command and option ----------------------------------------------------------------------------


def _subcommands() -> dict[str, argparse.ArgumentParser]:
    from hullstress.cli import build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return dict(sub.choices)


def _section(page: str, heading: str) -> str:
    text = (DOCS / page).read_text(encoding="utf-8")
    assert f"\n## {heading}\n" in text, f"docs/{page} has no section '## {heading}'"
    return text.split(f"\n## {heading}\n", 1)[1].split("\n## ", 1)[0]


@pytest.mark.parametrize("command", sorted(_subcommands()))
def test_every_option_of_every_subcommand_is_documented(command):
    section = _section("commands.md", command)
    missing = []
    for action in _subcommands()[command]._actions:
        if isinstance(action, argparse._HelpAction):
            continue
        if action.option_strings:
            for option in action.option_strings:
                if not re.search(rf"`{re.escape(option)}[`\s=\]]", section):
                    missing.append(option)
        elif action.metavar is not None and action.metavar not in section:
            missing.append(action.metavar)  # a positional argument, by the name --help shows
        for choice in action.choices or ():
            if not re.search(rf"\b{re.escape(str(choice))}\b", section):
                missing.append(f"{action.option_strings or action.dest} {choice}")
    assert not missing, f"docs/commands.md '## {command}' does not mention {missing}"


def test_the_readme_lists_every_command():
    listing = "\n".join(ln for ln in README.read_text(encoding="utf-8").splitlines()
                        if ln.startswith("python -m hullstress "))
    for command in _subcommands():
        assert f"python -m hullstress {command} " in listing, command


# -- the command blocks a user pastes ----------------------------------------------------------------------


@dataclass(frozen=True)
class Journey:
    """How the test runs one tagged block.

    ``files`` writes other tagged blocks into the folder first (tag -> file name).  ``smaller`` rewrites
    the command for the fast test (and says so: its docstring-like ``why``); ``None`` runs it as printed.
    ``covered_by`` names the test that already runs the block exactly as printed; ``check`` inspects
    the result.  ``needs`` lists programs that must be on PATH (Qhull's, installed by the qhull extra).
    """

    files: dict[str, str] = field(default_factory=dict)
    smaller: Callable[[str], str] | None = None
    why: str = ""
    expect: tuple[int, ...] = (0,)
    cwd_is_repo: bool = False
    needs: tuple[str, ...] = ()
    check: Callable[[Path, list[subprocess.CompletedProcess]], None] | None = None
    covered_by: str = ""
    file_only: bool = False
    slow_as_printed: bool = False
    one_shell: bool = False  # the block's lines share one shell (a variable set on one line, used on the next)
    known_bug: str = ""  # the command as printed hits this open bug: its slow test is a strict xfail until fixed


def _run_dir(cwd: Path, res: subprocess.CompletedProcess) -> Path:
    line = [ln for ln in res.stdout.splitlines() if ln.startswith("report: ")][-1]
    return cwd / line.split(": ", 1)[1]


def _check_quick_run(cwd, results):
    run = _run_dir(cwd, results[-1])
    for name in ("summary.md", "results.csv", "run.json", "report.html"):
        assert (run / name).is_file(), name
    assert json.loads((run / "run.json").read_text())["state"] == "complete"


def _check_chain(cwd, results):
    table = pd.read_csv(_run_dir(cwd, results[-1]) / "results.csv", keep_default_na=False)
    assert set(table["algorithm"]) == {"my-chain"}
    assert set(table.loc[table["generator"] == "uniform", "status"]) == {"pass"}  # as the page says
    failed = table[table["status"] == "fail"]
    assert len(failed) and set(failed["generator"]) <= {"near-collinear", "collinear-line"}


def _check_findings(cwd, results):
    run = _run_dir(cwd, results[0])
    assert (run / "findings.md").is_file() and (run / "findings.csv").is_file()
    assert "sphere method" in results[-1].stdout.lower()


def _findings_smaller(text: str) -> str:
    # The findings run as printed is 23,520 calls (about ten minutes on 2 cores): the fast test keeps
    # every generator and option but one size, two algorithms (one per dimension) and one eps policy.
    return text.replace("--sizes 16,64,256", "--sizes 16 --algorithm monotone-chain --algorithm kenwright --eps scaled")


def _quick_smaller(text: str) -> str:
    # The quick profile as printed (8,500 calls) is the slow test; the fast one runs the same command
    # on two families and two algorithms.
    return text + " --generator uniform --generator collinear-line --algorithm monotone-chain --algorithm kenwright"


def _check_nightly_by_hand(cwd, results):
    # The first night created the corpus (exit 1, every group new); the second night on the same code
    # finds nothing new and exits 0, as the page says.
    assert results[-1].stdout.strip().splitlines()[-1] == "1", results[-1].stdout[-2000:]  # the block's echo $?
    assert any((cwd / "corpus").glob("*.json"))
    again = subprocess.run(_commands(block("nightly-by-hand"))[0], shell=True, cwd=cwd, capture_output=True,
                           text=True, env=_env(), timeout=900)
    assert again.returncode == 0, again.stdout[-2000:] + again.stderr[-2000:]
    assert re.search(r"against baseline corpus: 0 new, \d+ still-failing", again.stdout), again.stdout[-2000:]


def _check_contract_runs(cwd, results):
    for res in results:
        run = _run_dir(cwd, res)
        table = pd.read_csv(run / "results.csv", keep_default_na=False)
        assert set(table["contract"]) == {"strict"} or set(table["contract"]) == {"strict,flat=raise"}, (
            set(table["contract"]))


def _check_real_qconvex(cwd, results):
    meta = json.loads((_run_dir(cwd, results[-1]) / "run.json").read_text())
    programs = [e["program"] for e in meta["executables"].values()]
    assert programs and all("cmeel.prefix" in p for p in programs), programs


def _quick_smaller_3d(text: str) -> str:
    # A program or plug-in on the whole quick profile is the slow test; the fast one runs two families.
    return text + " --generator uniform --generator cube-faces"


def _check_corpus_pytest(cwd, results):
    assert re.search(r"\b2 passed\b", results[-1].stdout), results[-1].stdout[-2000:]


JOURNEYS: dict[str, Journey] = {
    # README's Quick start: the set-up has run (this is its environment); the run itself is the journey.
    "run-command": Journey(smaller=_quick_smaller, why="two families, two algorithms",
                           expect=(0, 1), check=_check_quick_run, slow_as_printed=True),
    "test-command": Journey(covered_by=".ci/run (CI runs this line verbatim; test_public_api checks it)"),
    "plugin-example": Journey(file_only=True),
    "plugin-command": Journey(covered_by="tests/test_public_api.py::test_readme_plugin_example_runs_exactly_as_printed"),
    "exec-command": Journey(covered_by="tests/test_executable.py::test_readme_exec_example_runs_as_printed"),
    "plugin-example-2d": Journey(file_only=True),
    "plugin-command-2d": Journey(files={"plugin-example-2d": "my_chain.py"}, expect=(1,), check=_check_chain),
    "pytest-example": Journey(files={"plugin-example": "my_hulls.py", "plugin-example-2d": "my_chain.py"},
                              check=lambda cwd, res: None),
    "qhull-check": Journey(needs=("rbox", "qconvex")),
    "export-qconvex": Journey(needs=("qconvex",), cwd_is_repo=True),
    "findings": Journey(smaller=_findings_smaller, why="one size, two algorithms, one eps", expect=(0, 1),
                        check=_check_findings, slow_as_printed=True),
    "corpus-pytest": Journey(check=_check_corpus_pytest),
    # docs/nightly.md
    "nightly-workflow": Journey(covered_by="tests/test_nightly_workflow.py (five nights; "
                                "test_nightly_block_is_the_workflow_s checks the text)"),
    "nightly-by-hand": Journey(files={"plugin-example-2d": "my_chain.py"}, one_shell=True,
                               check=_check_nightly_by_hand),
    "replay-accept": Journey(covered_by="tests/test_corpus_loop.py (replay --accept after a fix)"),
    # docs/recovering-runs.md
    "report-command": Journey(covered_by="tests/test_first_hour.py::"
                              "test_a_crash_without_isolation_leaves_its_rows_and_the_report_command_makes_the_report"),
    # docs/executables.md
    "exec-driver-c": Journey(covered_by="tests/test_drivers.py::test_driver_is_fuzzed_by_the_quick_profile"),
    "exec-driver-js": Journey(covered_by="tests/test_drivers.py::test_driver_is_fuzzed_by_the_quick_profile"),
    "exec-driver-python": Journey(covered_by="tests/test_drivers.py::test_driver_is_fuzzed_by_the_quick_profile "
                                  "(the page's /path/to/other/venv is the user's)"),
    "exec-real-qconvex": Journey(needs=("qconvex",), one_shell=True, smaller=_quick_smaller_3d,
                                 why="two 3D families", expect=(0, 1), check=_check_real_qconvex,
                                 slow_as_printed=True),
    # docs/contracts.md
    "contract-command": Journey(files={"plugin-example": "my_hulls.py"}, needs=("qconvex",),
                                smaller=_quick_smaller_3d, why="two families", expect=(0, 1),
                                check=_check_contract_runs, slow_as_printed=True,
                                known_bug="on the whole quick profile the qhull2 line exits 3: "
                                "hullstress/report/handover.py _words() reads w['spanning'] of a zero signed-area "
                                "witness that has none (KeyError) while writing bug-report.md"),
    # docs/failure-folders.md
    "verify-certificate": Journey(covered_by="tests/test_handover.py::"
                                  "test_the_verifier_accepts_every_certificate_of_the_run"),
    "failure-folder-example": Journey(covered_by="tests/test_handover.py (repro.py, verify.py and bug-report.md "
                                      "in every failure folder of a run; the page's <run> is the user's)"),
    # docs/checker.md
    "adversarial-suite": Journey(covered_by="the suite itself (tests/test_checker_adversarial.py runs in CI; its slow "
                                            "form in the nightly workflow's slow tests)"),
    "mutation": Journey(covered_by="the nightly workflow's mutation job (test_mutation_block_is_the_workflow_s)"),
    "dask-scheduler": Journey(covered_by="test_dask_journey (slow)"),
    "dask-worker": Journey(covered_by="test_dask_journey (slow)"),
    "dask-run": Journey(covered_by="test_dask_journey (slow)"),
}


def test_every_command_block_is_tagged_and_known():
    untagged = []
    for path in _documents():
        text = path.read_text(encoding="utf-8")
        tagged_starts = {m.start(2) - 3 for m in TAG.finditer(text)}
        for m in FENCE.finditer(text):
            if m.group(1) in COMMAND_LANGUAGES and m.start() not in tagged_starts:
                untagged.append(f"{path.relative_to(ROOT)}: {m.group(2).splitlines()[0][:70]}")
    assert not untagged, "untagged command blocks (tag them, or mark a non-command block `text`): " + "; ".join(untagged)
    unknown = set(_tagged_blocks()) - set(JOURNEYS)
    assert not unknown, f"tagged blocks the test does not know how to run: {sorted(unknown)}"
    unused = set(JOURNEYS) - set(_tagged_blocks())
    assert not unused, f"journeys whose block is gone: {sorted(unused)}"


def _env() -> dict[str, str]:
    return {**os.environ, "PATH": f"{PY_BIN}{os.pathsep}{os.environ.get('PATH', '')}", "NO_MKDOCS_2_WARNING": "1"}


def _commands(text: str) -> list[str]:
    """The block's commands: one per line, a trailing backslash continuing a line."""
    return [c.strip() for c in text.replace("\\\n", " ").splitlines() if c.strip()]


def _play(tag: str, tmp_path: Path, *, as_printed: bool) -> None:
    journey = JOURNEYS[tag]
    for needed in journey.needs:
        if shutil.which(needed, path=_env()["PATH"]) is None:
            pytest.skip(f"{needed} is not installed: pip install cmeel-qhull (part of the qhull and all extras)")
    for other, name in journey.files.items():
        (tmp_path / name).write_text(block(other), encoding="utf-8")
    text = block(tag)
    if tag == "pytest-example":
        (tmp_path / "test_my_hulls.py").write_text(text, encoding="utf-8")
        commands = ["python -m pytest -q -p no:cacheprovider"]  # the page's "run python -m pytest"
    elif tag == "corpus-pytest":
        corpus = tmp_path / "tests" / "my_corpus"
        corpus.mkdir(parents=True)
        for entry in sorted((ROOT / "tests" / "corpus").glob("*.json"))[:2]:
            shutil.copy(entry, corpus / entry.name)
        (tmp_path / "test_corpus.py").write_text(text, encoding="utf-8")
        commands = ["python -m pytest -q -p no:cacheprovider test_corpus.py"]
    else:
        commands = _commands(text)
        if tag == "run-command":
            commands = [commands[0].rsplit(" && ", 1)[1]]  # the environment is set up: this is it
        if not as_printed and journey.smaller is not None:
            commands = [journey.smaller(c) if c.startswith("python -m hullstress run") else c for c in commands]
    if journey.one_shell:
        commands = ["\n".join(commands)]
    cwd = ROOT if journey.cwd_is_repo else tmp_path
    results: list[subprocess.CompletedProcess] = []
    for command in commands:
        if "<the run folder it printed>" in command:  # the findings block's second line
            command = command.replace("reports/<the run folder it printed>", str(_run_dir(cwd, results[-1])))
        res = subprocess.run(command, shell=True, cwd=cwd, capture_output=True, text=True, env=_env(),
                             timeout=3600)
        assert res.returncode in journey.expect or (results and res.returncode == 0), (
            f"{command!r} exited {res.returncode}: {res.stderr[-3000:]}")
        results.append(res)
    if journey.check is not None:
        journey.check(cwd, results)


def _runnable(slow: bool) -> list:
    params = []
    for tag, journey in sorted(JOURNEYS.items()):
        if journey.covered_by or journey.file_only:
            continue
        if slow and journey.slow_as_printed:
            marks = [pytest.mark.slow]
            if journey.known_bug:
                marks.append(pytest.mark.xfail(strict=True, raises=AssertionError, reason=journey.known_bug))
            params.append(pytest.param(tag, marks=marks, id=f"{tag}-as-printed"))
        elif not slow:
            params.append(pytest.param(tag, id=tag))
    return params


@pytest.mark.parametrize("tag", _runnable(slow=False))
def test_command_block_runs(tag, tmp_path):
    """Each block a user pastes, run in a fresh folder (with the smaller profile its journey names)."""
    _play(tag, tmp_path, as_printed=False)


@pytest.mark.parametrize("tag", _runnable(slow=True))
def test_command_block_runs_exactly_as_printed(tag, tmp_path):
    _play(tag, tmp_path, as_printed=True)


def test_covered_blocks_are_the_ones_their_tests_read():
    # The README's plug-in and --exec blocks are run by the tests named in JOURNEYS, which read the
    # README; the docs' copies must be the same text.
    for tag in ("plugin-example", "plugin-command", "exec-command"):
        assert len({text for _, _, text in _tagged_blocks()[tag]}) == 1, tag
        assert any(p == README for p, _, _ in _tagged_blocks()[tag]), tag


def test_nightly_block_is_the_workflow_s():
    """docs/nightly.md's sweep step is the workflow's, which tests/test_nightly_workflow.py runs for five nights."""
    workflow = (ROOT / ".github" / "workflows" / "nightly.yml").read_text(encoding="utf-8")
    joined = workflow.replace("\\\n", " ")
    lines = re.findall(r"^\s*(python -m hullstress (?:run|replay) .*)$", joined, re.M)
    assert [" ".join(c.split()) for c in _commands(block("nightly-workflow"))] == [" ".join(c.split()) for c in lines]


def test_mutation_block_is_the_workflow_s():
    """The mutation run takes hours: the nightly workflow's mutation job runs it, installed as the page says."""
    assert _commands(block("mutation")) == ['pip install -e ".[mutation]" && tools/mutation.sh']
    workflow = (ROOT / ".github" / "workflows" / "nightly.yml").read_text(encoding="utf-8")
    assert "run: tools/mutation.sh" in workflow and '".[all,mutation]"' in workflow
    assert os.access(ROOT / "tools" / "mutation.sh", os.X_OK)


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.mark.slow
def test_dask_journey(tmp_path):
    """docs/dask.md as a user follows it: a scheduler, a worker, then the run; its table equals a local run's."""
    if shutil.which("dask", path=_env()["PATH"]) is None:
        pytest.skip("dask is not installed: pip install -e '.[distributed]'")
    port = _free_port()
    address = f"tcp://127.0.0.1:{port}"
    scheduler_cmd = _commands(block("dask-scheduler"))[0].replace("--port 8786", f"--port {port} --host 127.0.0.1"
                                                                  " --dashboard-address :0")
    worker_cmd = _commands(block("dask-worker"))[0].replace("tcp://scheduler-host:8786", address)
    # Smaller than the quick profile as printed: one family, one algorithm per dimension.
    small = " --generator uniform --generator cube-faces --algorithm monotone-chain --algorithm kenwright --no-shrink"
    run_cmd = _commands(block("dask-run"))[0].replace("tcp://scheduler-host:8786", address) + small
    procs = []
    try:
        for command in (scheduler_cmd, worker_cmd):
            procs.append(subprocess.Popen(command, shell=True, cwd=tmp_path, env=_env(), start_new_session=True,
                                          stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
            time.sleep(3)
        (tmp_path / "dask").mkdir()
        (tmp_path / "local").mkdir()
        dask = subprocess.run(run_cmd, shell=True, cwd=tmp_path / "dask", capture_output=True, text=True,
                              env=_env(), timeout=900)
        local = subprocess.run("python -m hullstress run" + small, shell=True, cwd=tmp_path / "local",
                               capture_output=True, text=True, env=_env(), timeout=900)
    finally:
        for proc in procs:
            os.killpg(proc.pid, 15)
            proc.wait(timeout=30)
    assert dask.returncode in (0, 1), dask.stderr[-3000:]
    from hullstress.results import TIMING_COLUMNS

    tables = [pd.read_csv(_run_dir(d, r) / "results.csv", keep_default_na=False).drop(columns=list(TIMING_COLUMNS))
              for d, r in ((tmp_path / "dask", dask), (tmp_path / "local", local))]
    pd.testing.assert_frame_equal(*tables)
    meta = json.loads((_run_dir(tmp_path / "dask", dask) / "run.json").read_text())
    assert meta["runner"]["backend"] == "dask"
