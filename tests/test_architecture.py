"""The seams between stages, as docs/design.md ("The flow") describes them.

The report stage reads records and writes files: nothing under
``hullstress/report/`` may import a module that runs code under test (the
runner, evaluate, the shrinker and triage's stage) or the command line.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parent.parent / "hullstress"

#: Modules the report stage must not import (directly or by a relative import).
RUNS_CODE = ("hullstress.runner", "hullstress.evaluate", "hullstress.triage.shrink", "hullstress.triage.oracle",
             "hullstress.triage.stage", "hullstress.triage.evidence", "hullstress.triage.fuzzing",
             "hullstress.pipeline", "hullstress.cli")


def _imports(path: Path) -> set[str]:
    """Absolute names of every module ``path`` imports, at any depth of its code."""
    package = ".".join(path.relative_to(PACKAGE.parent).with_suffix("").parts[:-1])
    found: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                module = ".".join(base + ([node.module] if node.module else []))
            else:
                module = node.module or ""
            found.add(module)
            found.update(f"{module}.{alias.name}" for alias in node.names)
    return found


@pytest.mark.parametrize("path", sorted((PACKAGE / "report").glob("*.py")), ids=lambda p: p.name)
def test_report_stage_runs_nothing(path: Path) -> None:
    bad = sorted(m for m in _imports(path) if m.startswith(RUNS_CODE))
    assert not bad, f"{path.name} imports {bad}"


def test_the_import_rule_sees_relative_imports() -> None:
    # A guard on the guard: the triage stage does import the shrinker, relatively.
    assert "hullstress.triage.shrink.Shrinker" in _imports(PACKAGE / "triage" / "stage.py")
