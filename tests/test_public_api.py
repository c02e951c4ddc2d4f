"""The public surface: ``__all__``, the registries and the docs agree; the README's plug-in example runs as printed."""

import os
import re
import subprocess
import sys
from pathlib import Path

import pandas as pd

import hullstress
from hullstress._registry import algorithms, generators

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text(encoding="utf-8")
DOCS = ROOT / "docs"


def _block_after(marker: str) -> str:
    """The fenced block that follows ``<!-- marker -->`` in the README."""
    m = re.search(rf"<!-- {marker} -->\s*```[a-z]*\n(.*?)```", README, re.S)
    assert m, f"README has no fenced block after <!-- {marker} -->"
    return m.group(1)


def test_all_names_exist_and_are_exported():
    for name in hullstress.__all__:
        assert hasattr(hullstress, name), name
    assert len(set(hullstress.__all__)) == len(hullstress.__all__)
    for name in ("register_algorithm", "register_generator", "check", "Case", "Verdict", "AlgorithmConfig"):
        assert name in hullstress.__all__


def _page_table_names(page: str) -> set[str]:
    """The names in the first column of the tables of ``docs/<page>``."""
    text = (DOCS / page).read_text(encoding="utf-8")
    return set(re.findall(r"^\| `([A-Za-z0-9-]+)` \|", text, re.M))


def test_docs_list_every_registered_algorithm_and_nothing_else():
    registered = {s.name for s in algorithms() if s.origin in ("in-house", "adapter")}
    assert _page_table_names("algorithms.md") == registered


def test_docs_list_every_generator_family_and_nothing_else():
    built_in = {g.name for g in generators() if g.func.__module__.split(".")[0] == "generators"}
    assert _page_table_names("generators.md") == built_in


def test_readme_quick_start_has_exactly_the_two_commands():
    run = _block_after("run-command").strip().splitlines()
    test = _block_after("test-command").strip().splitlines()
    assert len(run) == 1 and run[0].endswith("python -m hullstress run")
    assert len(test) == 1 and test[0].endswith("python -m pytest")
    ci = (ROOT / ".ci" / "run").read_text()
    assert "test-command" in ci  # .ci/run executes the README's line, not a copy of it


def test_readme_plugin_example_runs_exactly_as_printed(tmp_path):
    (tmp_path / "my_hulls.py").write_text(_block_after("plugin-example"))
    command = _block_after("plugin-command").strip()
    env = dict(os.environ, PATH=f"{Path(sys.executable).parent}{os.pathsep}{os.environ.get('PATH', '')}")
    res = subprocess.run(command, shell=True, cwd=tmp_path, capture_output=True, text=True, env=env, timeout=600)
    assert res.returncode in (0, 1), res.stderr
    run_dir = Path(tmp_path, [l for l in res.stdout.splitlines() if l.startswith("report: ")][-1][8:])
    table = pd.read_csv(run_dir / "results.csv", keep_default_na=False)
    assert set(table["algorithm"]) == {"my-quickhull"}
    assert set(table["generator"]) == {"uniform", "cube-faces"}
    uniform = table[(table["generator"] == "uniform") & (table["sphere"] == "off")]
    assert len(uniform) > 0 and set(uniform["status"]) == {"pass"}


def test_docs_results_table_names_every_column():
    from hullstress.results import ROW_COLUMNS

    section = (DOCS / "results-table.md").read_text(encoding="utf-8")
    named = set(re.findall(r"`([a-z_]+)`", "\n".join(line.split("|")[1] for line in section.splitlines()
                                                       if line.startswith("| `"))))
    assert set(ROW_COLUMNS) <= named, sorted(set(ROW_COLUMNS) - named)
