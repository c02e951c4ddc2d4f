"""Replaying the regression corpus: every entry against every algorithm config of its dimension.

Each (entry, config) pair is classified against the recorded expectation:

``still-failing``  recorded a failure, fails the same way now
``fixed``          recorded a failure, passes (or is rejected) now
``changed``        recorded a failure, fails differently now       (regression)
``new-failure``    recorded no failure (or nothing), fails now      (regression)
``ok``             recorded no failure, none now
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import pandas as pd

from .._registry import algorithms, get_algorithm
from ..case import Case
from ..options import DEFAULTS
from ..config import AlgorithmConfig, expand_configs
from ..errors import CorpusError
from ..results import ResultRow
from ..runner import RunnerOptions, Task, execute
from .store import CorpusEntry, is_failure_signature, iter_corpus, row_signature, save_entry

__all__ = ["classify", "ReplayResult", "replay_entries", "replay_corpus", "record_expectations", "add_to_corpus", "REGRESSIONS"]

#: Outcomes that make replay exit 1.
REGRESSIONS = ("changed", "new-failure")


def classify(expected: str | None, actual: str) -> str:
    """Compare a recorded signature with the current one (see the module docstring)."""
    if expected is not None and is_failure_signature(expected):
        if actual == expected:
            return "still-failing"
        return "changed" if is_failure_signature(actual) else "fixed"
    return "new-failure" if is_failure_signature(actual) else "ok"


@dataclass
class ReplayResult:
    """Outcomes of one replay: a table of (entry, config) rows plus unreadable files."""

    table: pd.DataFrame
    errors: list[CorpusError] = field(default_factory=list)
    accepted: list[Path] = field(default_factory=list)

    @property
    def regressions(self) -> pd.DataFrame:
        return self.table[self.table["outcome"].isin(REGRESSIONS)]

    def per_entry(self) -> pd.DataFrame:
        """One row per entry: counts of each outcome."""
        if self.table.empty:
            return pd.DataFrame(columns=["entry", "family", "still-failing", "fixed", "changed", "new-failure", "ok"])
        counts = (
            self.table.groupby(["entry", "family", "outcome"]).size().unstack("outcome", fill_value=0)
            .reindex(columns=["still-failing", "fixed", "changed", "new-failure", "ok"], fill_value=0)
        )
        return counts.reset_index()


def _configs_for(entry: CorpusEntry, configs_by_dim: dict[int, list[AlgorithmConfig]],
                 recorded_only: bool) -> tuple[AlgorithmConfig, ...]:
    configs = configs_by_dim.get(entry.case.dim, [])
    if recorded_only:
        return tuple(c for c in configs if c.label in entry.expectations)
    return tuple(configs)


def replay_entries(
    entries: Sequence[CorpusEntry],
    *,
    algorithm_names: Sequence[str] = (),
    workers: int = 0,
    timeout: float = DEFAULTS.call_timeout,
    accept: bool = False,
    recorded_only: bool = False,
) -> ReplayResult:
    """Replay ``entries`` and classify every (entry, config) pair.

    Parameters
    ----------
    entries : sequence of CorpusEntry
    algorithm_names : sequence of str
        Restrict to these algorithms (default: every registered one).
    workers : int
        As for ``run --workers`` (0: in this process).
    timeout : float
        Per-call timeout when isolated.
    accept : bool
        Record the current signatures as the new expectations (after a fix).
    recorded_only : bool
        Replay only the configs an entry has an expectation for (the pytest
        plug-in does: other tests of a session may register algorithms of
        their own, which are no regression of the corpus).
    """
    specs = [get_algorithm(n) for n in algorithm_names] if algorithm_names else algorithms()
    configs_by_dim = {d: expand_configs([s for s in specs if s.dim == d]) for d in (2, 3)}
    tasks = [Task(index=i, case=e.case, configs=_configs_for(e, configs_by_dim, recorded_only)) for i, e in enumerate(entries)]
    tasks = [t for t in tasks if t.configs]
    rows: list[ResultRow] = []
    execute(tasks, RunnerOptions(workers=workers, timeout=timeout, qhull=True), rows.append)
    by_case = {e.case.case_id: e for e in entries}
    records = []
    current: dict[str, dict[str, str]] = {}
    for row in rows:
        entry = by_case[row["case_id"]]
        actual = row_signature(row)
        expected = entry.expectations.get(row["config"])
        current.setdefault(entry.entry_id, {})[row["config"]] = actual
        records.append(
            {
                "entry": entry.entry_id,
                "file": entry.path.name if entry.path else "",
                "family": entry.case.family,
                "n_points": entry.case.n_points,
                "config": row["config"],
                "expected": expected if expected is not None else "",
                "actual": actual,
                "outcome": classify(expected, actual),
                "reason": row["reason"],
            }
        )
    table = pd.DataFrame.from_records(
        records, columns=["entry", "file", "family", "n_points", "config", "expected", "actual", "outcome", "reason"]
    ).sort_values(["entry", "config"], kind="mergesort").reset_index(drop=True)
    result = ReplayResult(table=table)
    if accept:
        for entry in entries:
            if entry.path is None or entry.entry_id not in current:
                continue
            merged = {**entry.expectations, **current[entry.entry_id]}
            path, _ = save_entry(entry.path.parent, entry.with_expectations(merged), overwrite=True)
            result.accepted.append(path)
    return result


def replay_corpus(
    directory: str | os.PathLike[str],
    **kwargs: object,
) -> ReplayResult:
    """Load every corpus file under ``directory`` (bad files become errors) and replay the rest."""
    entries: list[CorpusEntry] = []
    errors: list[CorpusError] = []
    for _, item in iter_corpus(directory):
        if isinstance(item, CorpusError):
            errors.append(item)
        else:
            entries.append(item)
    result = replay_entries(entries, **kwargs)  # type: ignore[arg-type]
    result.errors = errors
    return result


def record_expectations(
    cases: Sequence[Case], *, workers: int = 0, timeout: float = DEFAULTS.call_timeout, algorithm_names: Sequence[str] = ()
) -> dict[str, dict[str, str]]:
    """Run every config on each case; return ``{case_id: {config label: signature}}``."""
    specs = [get_algorithm(n) for n in algorithm_names] if algorithm_names else algorithms()
    configs_by_dim = {d: expand_configs([s for s in specs if s.dim == d]) for d in (2, 3)}
    tasks = [Task(index=i, case=c, configs=tuple(configs_by_dim.get(c.dim, []))) for i, c in enumerate(cases)]
    rows: list[ResultRow] = []
    execute([t for t in tasks if t.configs], RunnerOptions(workers=workers, timeout=timeout, qhull=True), rows.append)
    out: dict[str, dict[str, str]] = {c.case_id: {} for c in cases}
    for row in rows:
        out[row["case_id"]][row["config"]] = row_signature(row)
    return out


def add_to_corpus(
    directory: str | os.PathLike[str],
    cases: Sequence[tuple[Case, dict]],
    *,
    workers: int = 0,
    timeout: float = DEFAULTS.call_timeout,
) -> list[tuple[Path, bool]]:
    """Add cases (each with its provenance) to the corpus, recording every config's current verdict.

    Returns
    -------
    list of (path, written)
        ``written`` is False for cases already in the corpus (same content hash).
    """
    expectations = record_expectations([c for c, _ in cases], workers=workers, timeout=timeout)
    out = []
    for case, provenance in cases:
        entry = CorpusEntry(case=case, expectations=expectations[case.case_id], provenance=provenance)
        out.append(save_entry(directory, entry))
    return out
