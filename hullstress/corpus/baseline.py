"""``run --baseline``: which failure groups of a run are new, still failing, fixed or not reached.

A failure group is a :class:`~hullstress.triage.signature.Signature` (the one
identity of "the same failure").  A baseline is the set of groups known to
fail: those of an earlier run (its folder, or its ``results.csv`` /
``results.parquet``) or those a regression corpus holds as failing (one entry
per group).  Against it, every group of the run or the baseline gets a state:

``new``            failed tonight, unknown to the baseline (the only state that makes ``run`` exit 1)
``still-failing``  failed tonight and is known; or, for a corpus, not met by the sweep but its entry's
                   case still fails exactly that way
``fixed``          known, its config's every planned call ran and none failed that way, and (for a
                   corpus) its entry's case no longer fails that way
``not-reached``    known, but its config's planned calls did not all run (``--time-budget``)

Groups of configs the run did not select are left out.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import pandas as pd

from ..errors import CorpusError, UsageError
from ..results import RESULTS_FILES, read_frame
from ..triage.grouping import FailureGroup, group_failures
from ..triage.signature import Signature, signature_of
from .store import CorpusEntry, held_groups

__all__ = ["STATES", "COMPARISON_COLUMNS", "Baseline", "load_baseline", "compare_with_baseline"]

#: The states of a group against a baseline, in report order.
STATES = ("new", "still-failing", "fixed", "not-reached")
#: Columns of :func:`compare_with_baseline`'s table.
COMPARISON_COLUMNS = ("state", "label", "group_id", "algorithm", "sphere", "eps", "stage", "status", "checks",
                      "severity", "error", "frame", "failures", "families", "how")


@dataclass(frozen=True)
class Baseline:
    """The failure groups known to fail.

    Attributes
    ----------
    groups : frozenset of Signature
    entries : mapping of Signature to CorpusEntry
        For a corpus: the entry holding each group (its case can be re-run); empty for a run.
    note : str
        One line for the terminal (a corpus that does not exist yet), or ``""``.
    """

    groups: frozenset[Signature]
    entries: Mapping[Signature, CorpusEntry] = field(default_factory=dict)
    note: str = ""


def _from_table(table: pd.DataFrame) -> Baseline:
    keep = [c for c in table.columns if c in ("algorithm", "sphere", "eps", "stage", "status", "reason",
                                                  "failed_checks", "severity", "error_frame")]
    sigs = (signature_of(row) for row in table[keep].to_dict("records"))
    return Baseline(groups=frozenset(s for s in sigs if s is not None))


def load_baseline(path: str | os.PathLike[str], *, may_be_created: bool = False) -> Baseline:
    """The failure groups of a baseline: a run folder, a results.csv/.parquet, or a corpus folder/file.

    Parameters
    ----------
    path : path
    may_be_created : bool
        ``path`` is also the folder ``--save-corpus`` writes: when it does not
        exist yet it is an empty corpus (the first night), not an error.

    Raises
    ------
    UsageError
        When ``path`` is none of these, or a corpus file in it is unreadable, naming it.
    """
    p = Path(path)
    if not p.exists():
        if may_be_created:
            return Baseline(frozenset(), note=f"--baseline {str(path)!r} does not exist yet: every failure group "
                            "is new, and --save-corpus creates it")
        raise UsageError(f"--baseline {str(path)!r}: no such file or directory")
    if p.is_dir():
        for name in RESULTS_FILES:
            if (p / name).exists():
                return load_baseline(p / name)
        if any(p.glob("*.json")) or not any(p.iterdir()) or may_be_created:
            return _from_corpus(p)
        raise UsageError(f"--baseline {str(path)!r}: neither a run folder (results.csv) nor a corpus folder (*.json)")
    if p.suffix == ".json":
        return _from_corpus(p)
    if p.suffix not in (".parquet", ".csv"):
        raise UsageError(f"--baseline {str(path)!r}: expected a run folder, results.csv, results.parquet or a corpus")
    try:
        table = read_frame(p)
    except (OSError, ValueError, ImportError) as exc:
        raise UsageError(f"--baseline {str(path)!r}: cannot read: {exc}") from None
    return _from_table(table)


def _from_corpus(path: Path) -> Baseline:
    try:
        held = held_groups(path)
    except CorpusError as exc:
        raise UsageError(f"--baseline: {exc}") from None
    return Baseline(groups=frozenset(held), entries=held)


def compare_with_baseline(
    table: pd.DataFrame,
    baseline: Baseline,
    planned: Mapping[str, int],
    *,
    recheck: Callable[[Sequence[CorpusEntry]], Mapping[Signature, bool]] | None = None,
    groups: Sequence[FailureGroup] | None = None,
) -> pd.DataFrame:
    """Every failure group of the run or the baseline, with its ``state`` (see the module docstring).

    Parameters
    ----------
    table : DataFrame
        The run's results.
    baseline : Baseline
    planned : mapping of str to int
        Calls the run planned per config label (a config absent is not compared).
    recheck : callable, optional
        Given corpus entries, whether each one's group still fails that way on
        its case (:func:`hullstress.corpus.replay.recheck_groups`); without it
        a group the sweep did not meet is fixed on the sweep's word alone.
    groups : sequence of FailureGroup, optional
        The run's groups when already computed (``group_failures(table)`` otherwise).

    Returns
    -------
    DataFrame
        :data:`COMPARISON_COLUMNS`, one row per group, by state then label.
    """
    current = {g.signature: g for g in (groups if groups is not None else group_failures(table))}
    done = table["config"].value_counts().to_dict() if len(table) and "config" in table else {}
    rows = []
    for sig, group in current.items():
        state = "still-failing" if sig in baseline.groups else "new"
        rows.append(_row(state, sig, group.count, " ".join(f"{f}:{n}" for f, n in group.families), "sweep"))
    unseen = [s for s in baseline.groups if s not in current and s.config.label in planned]
    reached = [s for s in unseen if done.get(s.config.label, 0) >= planned[s.config.label]]
    still: Mapping[Signature, bool] = {}
    if recheck is not None and baseline.entries and reached:
        still = recheck([baseline.entries[s] for s in reached if s in baseline.entries])
    for sig in unseen:
        if sig not in reached:
            rows.append(_row("not-reached", sig, 0, "", "its config's planned calls did not all run"))
        elif still.get(sig, False):
            rows.append(_row("still-failing", sig, 0, "", "not met by the sweep; its corpus case still fails so"))
        else:
            how = "the sweep and its corpus case" if sig in still else "the sweep"
            rows.append(_row("fixed", sig, 0, "", f"no longer fails so in {how}"))
    order = {s: i for i, s in enumerate(STATES)}
    rows.sort(key=lambda r: (order[r["state"]], r["label"]))
    return pd.DataFrame.from_records(rows, columns=list(COMPARISON_COLUMNS))


def _row(state: str, sig: Signature, failures: int, families: str, how: str) -> dict[str, object]:
    return {"state": state, "label": sig.label, "group_id": sig.group_id, **sig.as_dict(), "failures": failures,
            "families": families, "how": how}
