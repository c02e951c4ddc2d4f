"""The previous run in an output folder, for ``run --last-failed`` and ``run --failed-first``.

As pytest's options of the same names do with its cache, these read the
latest run folder under ``--out`` (the one whose ``results.csv``, or
``results.partial.csv`` for a run that was killed, is newest) and take the
(case id, config) calls that failed there: those with a failure signature
(:func:`hullstress.triage.signature.signature_of`; ``fail``, ``error``,
``timeout``, ``crash``).  Case ids are stable across runs (hashes of the exact points and
their provenance), so the same options regenerate the same cases.

* ``only`` (``--last-failed``): run just those calls; when the previous run
  had none, or none of them is in this run's plan, run everything (and say so).
* ``first`` (``--failed-first``): run the cases with a failed call first,
  then the rest; the results table is sorted as usual.
"""

from __future__ import annotations

import csv
import os
from collections.abc import Sequence
from pathlib import Path

from .runner import Task
from .triage.signature import signature_of

__all__ = ["latest_run", "failed_calls", "select_previous_failures", "MODES"]

#: ``only`` for --last-failed, ``first`` for --failed-first.
MODES = ("only", "first")
_RESULTS = ("results.csv", "results.partial.csv")


def latest_run(out: str | os.PathLike[str]) -> Path | None:
    """The run folder under ``out`` with the newest results file, or None when there is none."""
    base = Path(out)
    if not base.is_dir():
        return None
    best: tuple[float, Path] | None = None
    for folder in base.iterdir():
        for name in _RESULTS:
            path = folder / name
            if path.is_file():
                stamp = path.stat().st_mtime
                if best is None or stamp > best[0]:
                    best = (stamp, folder)
                break
    return None if best is None else best[1]


def failed_calls(run_dir: Path) -> set[tuple[str, str]]:
    """The (case id, config label) pairs that failed in ``run_dir``'s results."""
    path = next((run_dir / n for n in _RESULTS if (run_dir / n).is_file()), None)
    if path is None:
        return set()
    failed = set()
    with open(path, newline="", encoding="utf-8") as fh:
        for row in csv.DictReader(fh):
            if signature_of(row) is not None:  # a failure as triage and the corpus count one
                failed.add((row.get("case_id", ""), row.get("config", "")))
    return failed


def select_previous_failures(tasks: Sequence[Task], out: str | os.PathLike[str], mode: str) -> tuple[list[Task], str]:
    """Apply ``--last-failed`` (``mode="only"``) or ``--failed-first`` (``"first"``) to a plan's tasks.

    Returns
    -------
    tasks : list of Task
    note : str
        One line for the terminal: what was selected and from which run.
    """
    if mode not in MODES:
        raise ValueError(f"mode must be one of {MODES}, got {mode!r}")
    option = "--last-failed" if mode == "only" else "--failed-first"
    previous = latest_run(out)
    if previous is None:
        return list(tasks), f"{option}: no previous run in {str(out)!r}; running everything"
    failed = failed_calls(previous)
    if not failed:
        return list(tasks), f"{option}: no call failed in {previous.name}; running everything"
    failed_cases = {case_id for case_id, _ in failed}
    if mode == "first":
        first = [t for t in tasks if t.case.case_id in failed_cases]
        rest = [t for t in tasks if t.case.case_id not in failed_cases]
        return first + rest, f"{option}: {len(first)} cases that failed in {previous.name} run first"
    kept = []
    for task in tasks:
        configs = tuple(c for c in task.configs if (task.case.case_id, c.label) in failed)
        if configs:
            kept.append(Task(index=task.index, case=task.case, configs=configs))
    if not kept:
        return list(tasks), (f"{option}: none of the {len(failed)} calls that failed in {previous.name} is in "
                             "this run's plan; running everything")
    n = sum(len(t.configs) for t in kept)
    return kept, f"{option}: running the {n} calls that failed in {previous.name} (of {len(failed)})"
