"""One home per concept: the words a row's status, stage, severity, sphere, eps and origin hold live in
``hullstress.records``; code elsewhere names the enum member, never the string.

The scan reads every module of the package and flags a string literal that is one of those words where
it is used *as* one of them: compared with (or tested for membership in) an expression that mentions a
vocabulary column, passed as such a keyword argument, listed in ``.isin(...)`` on such a column, or
collected in a module-level constant named after one.  Docstrings and doctest examples are prose and are
not scanned.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import hullstress
from hullstress.records import NO_EPS, EpsPolicy, Origin, Severity, Sphere, Stage, Status

PACKAGE = Path(hullstress.__file__).parent
#: The columns (and attributes) whose values are vocabulary words.
COLUMNS = ("status", "stage", "severity", "sphere", "eps", "origin")
WORDS = frozenset(
    {m.value for enum in (Status, Severity, Sphere, EpsPolicy, Stage, Origin) for m in enum} | {NO_EPS}
)


def _mentions_column(node: ast.AST) -> bool:
    text = ast.unparse(node).lower()
    return any(column in text for column in COLUMNS)


def _word_literals(node: ast.AST) -> list[ast.Constant]:
    """The vocabulary-word string constants in ``node`` itself or one level of tuple/list/set inside it."""
    items = node.elts if isinstance(node, (ast.Tuple, ast.List, ast.Set)) else [node]
    return [c for c in items if isinstance(c, ast.Constant) and isinstance(c.value, str) and c.value in WORDS]


def literal_uses(source: str) -> list[tuple[int, str]]:
    """``(line, word)`` for every vocabulary literal used as a vocabulary value in ``source``.

    Examples
    --------
    >>> literal_uses('if row["status"] == "fail": pass')
    [(1, 'fail')]
    >>> literal_uses('make_row(case, status="error")')
    [(1, 'error')]
    >>> literal_uses('kind = "crash" if died else "ok"')  # another vocabulary sharing a word
    []
    >>> literal_uses('t["status"].isin(["fail", "error"])')
    [(1, 'fail'), (1, 'error')]
    """
    found: list[tuple[int, str]] = []
    for node in ast.walk(ast.parse(source)):
        hits: list[ast.Constant] = []
        if isinstance(node, ast.Compare):
            sides = [node.left, *node.comparators]
            if any(_mentions_column(side) for side in sides if not _word_literals(side)):
                for side in sides:
                    hits += _word_literals(side)
        elif isinstance(node, ast.Call):
            for kw in node.keywords:
                if kw.arg in COLUMNS or kw.arg == "sphere_method":
                    hits += _word_literals(kw.value)
            func = node.func
            if isinstance(func, ast.Attribute) and func.attr == "isin" and _mentions_column(func.value):
                for arg in node.args:
                    hits += _word_literals(arg)
        elif isinstance(node, ast.Assign) and any(
            isinstance(t, ast.Name) and any(c in t.id.lower() for c in COLUMNS) for t in node.targets
        ):
            hits += _word_literals(node.value)
        found += [(c.lineno, c.value) for c in hits]
    return sorted(found)


def _modules() -> list[Path]:
    return sorted(p for p in PACKAGE.rglob("*.py") if p.name != "records.py")


@pytest.mark.parametrize("path", _modules(), ids=lambda p: p.relative_to(PACKAGE).as_posix())
def test_vocabulary_words_are_enum_members_outside_records(path):
    uses = literal_uses(path.read_text(encoding="utf-8"))
    where = ", ".join(f"line {line} {word!r}" for line, word in uses)
    assert not uses, f"{path.relative_to(PACKAGE)}: use the hullstress.records member, not the string: {where}"


def test_the_scan_sees_a_planted_literal():
    planted = 'def f(row):\n    return row.status in ("timeout", "crash")\n'
    assert literal_uses(planted) == [(2, "crash"), (2, "timeout")]


def test_members_print_as_their_values():
    assert f"{Status.FAIL}" == "fail" and str(Sphere.ON) == "on" and "%s" % EpsPolicy.FIXED == "fixed"
    assert Status("rejected") is Status.REJECTED and Severity.GROSS == "gross"
