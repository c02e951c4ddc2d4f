"""pytest integration: replay a regression corpus as one test per entry.

Installed with hullstress (entry point ``pytest11``), so in any suite::

    import pytest

    @pytest.mark.hullstress_corpus("tests/corpus")
    def test_corpus(hullstress_corpus_entry):
        hullstress_corpus_entry.assert_no_regression()

collects one test per corpus file, named after the entry.  A test fails when
its entry regressed (a config fails differently, or newly fails), listing the
expected and actual signatures; a corrupt file fails its own test with the
corpus error while the others still run.  ``--hullstress-corpus DIR``
overrides the folder from the command line; ``--hullstress-workers N`` sets
the isolation (default 2 worker processes; 0 runs in-process).

The whole folder is replayed once per session (in parallel, isolated), and
each test reads its entry's outcomes from that shared result.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest

__all__ = ["CorpusCase", "assert_no_regression", "corpus_files"]

_CACHE: dict[tuple[str, int], Any] = {}


def corpus_files(directory: str | os.PathLike[str]) -> list[Path]:
    """The corpus files of ``directory``, sorted (hidden temporaries excluded)."""
    d = Path(directory)
    return sorted(p for p in d.glob("*.json") if not p.name.startswith(".")) if d.is_dir() else []


def _replayed(directory: Path, workers: int) -> Any:
    from .corpus.replay import replay_corpus

    key = (str(directory.resolve()), workers)
    if key not in _CACHE:
        _CACHE[key] = replay_corpus(directory, workers=workers, recorded_only=True)
    return _CACHE[key]


@dataclass(frozen=True)
class CorpusCase:
    """One corpus file as seen by a test."""

    path: Path
    workers: int = 2

    def outcomes(self) -> Any:
        """This entry's rows of the session's replay table (raises the corpus error if unreadable)."""
        from .corpus.store import load_entry

        entry = load_entry(self.path)  # raises CorpusError naming the file
        result = _replayed(self.path.parent, self.workers)
        return result.table[result.table["entry"] == entry.entry_id]

    def assert_no_regression(self) -> None:
        """Fail with the expected and actual signature of every regressed config."""
        from .corpus.replay import REGRESSIONS

        table = self.outcomes()
        bad = table[table["outcome"].isin(REGRESSIONS)]
        if len(bad):
            lines = [
                f"  {r.config}: expected {r.expected or '(nothing recorded)'}, got {r.actual} ({r.outcome}) {r.reason}"
                for r in bad.itertuples(index=False)
            ]
            raise AssertionError(f"corpus entry {self.path.name} regressed in {len(bad)} configs:\n" + "\n".join(lines))


def assert_no_regression(path: str | os.PathLike[str], *, workers: int = 2) -> None:
    """Replay one corpus file (with its folder) and fail on any regression."""
    CorpusCase(Path(path), workers).assert_no_regression()


def pytest_addoption(parser: pytest.Parser) -> None:
    group = parser.getgroup("hullstress")
    group.addoption("--hullstress-corpus", default=None, metavar="DIR",
                    help="corpus folder for tests marked hullstress_corpus (overrides the marker's folder)")
    group.addoption("--hullstress-workers", type=int, default=2, metavar="N",
                    help="worker processes for corpus replay (0: in-process)")


def pytest_configure(config: pytest.Config) -> None:
    config.addinivalue_line(
        "markers", "hullstress_corpus(directory): parametrize hullstress_corpus_entry over a corpus folder"
    )


def pytest_generate_tests(metafunc: pytest.Metafunc) -> None:
    if "hullstress_corpus_entry" not in metafunc.fixturenames:
        return
    marker = metafunc.definition.get_closest_marker("hullstress_corpus")
    directory = metafunc.config.getoption("--hullstress-corpus") or (marker.args[0] if marker and marker.args else None)
    if directory is None:
        raise pytest.UsageError(
            f"{metafunc.definition.nodeid}: hullstress_corpus_entry needs @pytest.mark.hullstress_corpus(DIR) "
            "or --hullstress-corpus DIR"
        )
    directory = Path(directory)
    if not directory.is_absolute():
        directory = Path(metafunc.config.rootpath) / directory
    workers = metafunc.config.getoption("--hullstress-workers")
    files = corpus_files(directory)
    metafunc.parametrize(
        "hullstress_corpus_entry",
        [CorpusCase(p, workers) for p in files],
        ids=[p.stem for p in files],
    )
