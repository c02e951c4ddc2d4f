"""Every docstring example of the package runs as a test, so an example that lies fails.

One test per module of ``hullstress`` and ``generators`` (found by walking the
packages, so a new module is collected without a list to update).  Examples
run in their module's namespace, as ``python -m doctest`` would run them.
"""

from __future__ import annotations

import doctest
import importlib
import pkgutil

import pytest

import generators
import hullstress

PACKAGES = (hullstress, generators)
FLAGS = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE


def _module_names() -> list[str]:
    names = []
    for package in PACKAGES:
        names.append(package.__name__)
        for info in pkgutil.walk_packages(package.__path__, prefix=package.__name__ + "."):
            if not info.name.rsplit(".", 1)[-1].startswith("__"):
                names.append(info.name)
    return sorted(names)


MODULES = _module_names()
#: Modules whose examples take long: Hypothesis's ``find`` shrinks each draw to the minimal
#: example (about 40 s for hullstress.strategies); they run with the nightly slow tests.
SLOW = {"hullstress.strategies"}


def test_the_walk_finds_the_checker():
    assert {"hullstress.checker.api", "hullstress.checker.severity", "hullstress.contract"} <= set(MODULES)


@pytest.mark.parametrize("name", [pytest.param(m, marks=pytest.mark.slow) if m in SLOW else m for m in MODULES])
def test_docstring_examples(name):
    try:
        module = importlib.import_module(name)
    except ImportError as exc:  # an adapter whose optional library is not installed
        pytest.skip(f"{name} needs an optional dependency: {exc}")
    finder = doctest.DocTestFinder(exclude_empty=True)
    tests = [t for t in finder.find(module, name) if t.examples]
    if not tests:
        return
    failures = []
    for test in tests:
        runner = doctest.DocTestRunner(optionflags=FLAGS)
        out: list[str] = []
        runner.run(test, out=out.append)
        if runner.failures:
            failures.append("".join(out))
    assert not failures, "\n".join(failures)
