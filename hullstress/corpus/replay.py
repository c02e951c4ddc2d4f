"""Replaying the regression corpus: every entry against every algorithm config of its dimension.

Each (entry, config) pair is classified by comparing the call's verdict now
with the recorded one (:func:`~hullstress.triage.signature.verdict_of`: the
failure's signature, so "the same way" means the same failure group):

=================  ===============================================  ==========
outcome            recorded -> now                                  exit status
=================  ===============================================  ==========
``still-failing``  a failure -> the same failure                    0
``fixed``          a failure -> pass or rejected                    0
``changed``        a failure -> a different failure                 1
``new-failure``    pass, rejected or nothing -> a failure           1
``ok``             pass, rejected or nothing -> pass or rejected    0
=================  ===============================================  ==========

``changed`` turns CI red: the case now fails in a way nobody has recorded,
which may be a partial fix or a new bug; only a person can tell, and
``replay --accept`` records the verdict once they have (``run --baseline``
says the same of the same change: a new failure group).
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
from ..triage.signature import Signature, is_failure_verdict, verdict_of
from .store import FAILING, FIXED, CorpusEntry, iter_corpus, save_entry

__all__ = ["classify", "ReplayResult", "replay_entries", "replay_corpus", "record_expectations", "add_to_corpus",
           "recheck_groups", "OUTCOMES", "REGRESSIONS"]

#: Every outcome, in the order the summary counts them.
OUTCOMES = ("still-failing", "fixed", "changed", "new-failure", "ok")
#: Outcomes that make replay exit 1.
REGRESSIONS = ("changed", "new-failure")


def classify(expected: str | None, actual: str) -> str:
    """Compare a recorded verdict with the current one (see the module docstring).

    Examples
    --------
    >>> classify("fail containment (gross)", "fail convexity (gross)"), classify("pass", "error KeyError")
    ('changed', 'new-failure')
    """
    if is_failure_verdict(expected):
        if actual == expected:
            return "still-failing"
        return "changed" if is_failure_verdict(actual) else "fixed"
    return "new-failure" if is_failure_verdict(actual) else "ok"


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
            return pd.DataFrame(columns=["entry", "family", *OUTCOMES])
        counts = (
            self.table.groupby(["entry", "family", "outcome"]).size().unstack("outcome", fill_value=0)
            .reindex(columns=list(OUTCOMES), fill_value=0)
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
        Record the current verdicts as the new expectations (after a fix); an
        entry whose group's config no longer fails that way becomes ``fixed``.
    recorded_only : bool
        Replay only the configs an entry has an expectation for (the pytest
        plug-in does: other tests of a session may register algorithms of
        their own, which are no regression of the corpus).
    """
    specs = [get_algorithm(n) for n in algorithm_names] if algorithm_names else algorithms()
    configs_by_dim = {d: expand_configs([s for s in specs if s.dim == d]) for d in (2, 3)}
    # Two groups may share one minimal case (one entry each): each (case, config) runs once, for all of them.
    wanted: dict[str, dict[str, AlgorithmConfig]] = {}
    sharing: dict[str, list[CorpusEntry]] = {}
    cases: dict[str, Case] = {}
    for e in entries:
        configs = _configs_for(e, configs_by_dim, recorded_only)
        if configs:
            cases.setdefault(e.case.case_id, e.case)
            sharing.setdefault(e.case.case_id, []).append(e)
            wanted.setdefault(e.case.case_id, {}).update((c.label, c) for c in configs)
    tasks = [Task(index=i, case=cases[cid], configs=tuple(wanted[cid].values())) for i, cid in enumerate(cases)]
    rows: list[ResultRow] = []
    execute(tasks, RunnerOptions(workers=workers, timeout=timeout, qhull=True), rows.append)
    records = []
    current: dict[str, dict[str, str]] = {}
    pairs = [(entry, row) for row in rows for entry in sharing[row["case_id"]]
             if recorded_only is False or row["config"] in entry.expectations]
    for entry, row in pairs:
        actual = verdict_of(row)
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
            state = entry.state
            if entry.group is not None and entry.group.config.label in current[entry.entry_id]:
                state = FAILING if merged[entry.group.config.label] == entry.group.what else FIXED
            path, _ = save_entry(entry.path.parent, entry.with_expectations(merged, state), overwrite=True)
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


def recheck_groups(entries: Sequence[CorpusEntry], options: RunnerOptions) -> dict[Signature, bool]:
    """Whether each entry's group config still fails exactly that way on the entry's case.

    ``run --baseline`` asks this of the groups a complete sweep did not see
    before it calls one fixed: a sweep with another seed or profile may simply
    not have met the group.
    """
    held = [e for e in entries if e.group is not None]
    tasks = [Task(index=i, case=e.case, configs=(e.group.config,)) for i, e in enumerate(held)]  # type: ignore[union-attr]
    rows: list[ResultRow] = []
    if tasks:
        execute(tasks, options, rows.append)
    verdicts = {(row["case_id"], row["config"]): verdict_of(row) for row in rows}
    return {e.group: verdicts.get((e.case.case_id, e.group.config.label)) == e.group.what  # type: ignore[union-attr]
            for e in held}


def record_expectations(
    cases: Sequence[Case], *, workers: int = 0, timeout: float = DEFAULTS.call_timeout, algorithm_names: Sequence[str] = ()
) -> dict[str, dict[str, str]]:
    """Run every config on each case; return ``{case_id: {config label: verdict}}``."""
    specs = [get_algorithm(n) for n in algorithm_names] if algorithm_names else algorithms()
    configs_by_dim = {d: expand_configs([s for s in specs if s.dim == d]) for d in (2, 3)}
    tasks = [Task(index=i, case=c, configs=tuple(configs_by_dim.get(c.dim, []))) for i, c in enumerate(cases)]
    rows: list[ResultRow] = []
    execute([t for t in tasks if t.configs], RunnerOptions(workers=workers, timeout=timeout, qhull=True), rows.append)
    out: dict[str, dict[str, str]] = {c.case_id: {} for c in cases}
    for row in rows:
        out[row["case_id"]][row["config"]] = verdict_of(row)
    return out


def add_to_corpus(
    directory: str | os.PathLike[str],
    cases: Sequence[tuple[Case, dict] | tuple[Case, dict, Signature | None]],
    *,
    workers: int = 0,
    timeout: float = DEFAULTS.call_timeout,
    overwrite: bool = False,
) -> list[tuple[Path, bool]]:
    """Add cases to the corpus, recording every config's current verdict.

    Parameters
    ----------
    directory : path
    cases : sequence of (case, provenance) or (case, provenance, group)
        ``group`` is the failure group the case is the minimal case of (None
        or absent: a plain regression case).
    overwrite : bool
        Replace an entry of the same id (a group the corpus recorded as fixed that fails again).

    Returns
    -------
    list of (path, written)
        ``written`` is False for entries already in the corpus (same group, or for a plain case the same points).
    """
    expectations = record_expectations([item[0] for item in cases], workers=workers, timeout=timeout)
    out = []
    for case, provenance, *rest in cases:
        group = rest[0] if rest else None
        entry = CorpusEntry(case=case, expectations=expectations[case.case_id], provenance=provenance, group=group)
        out.append(save_entry(directory, entry, overwrite=overwrite))
    return out
