"""Comparing a run with a baseline: which failure groups are new, still failing, or fixed.

A failure group is (algorithm, sphere, eps, family, signature), the signature
being :func:`hullstress.corpus.store.row_signature` (``fail:containment``,
``error``, ``crash`` ...).  A baseline is an earlier run (its folder or its
``results.csv`` / ``results.parquet``) or a regression corpus (its recorded
expectations).
"""

from __future__ import annotations

import os
from pathlib import Path

import pandas as pd

from ..config import AlgorithmConfig
from ..errors import CorpusError, UsageError
from ..results import RESULTS_FILES, read_frame
from .store import is_failure_signature, iter_corpus, row_signature

__all__ = ["GROUP_KEYS", "failure_groups", "load_baseline", "compare_with_baseline"]

GROUP_KEYS = ("algorithm", "sphere", "eps", "generator", "signature")


def failure_groups(table: pd.DataFrame) -> pd.DataFrame:
    """Failure groups of a results table with their row counts (column ``calls``)."""
    if table.empty:
        return pd.DataFrame(columns=list(GROUP_KEYS) + ["calls"])
    sig = table.apply(lambda r: row_signature(r.to_dict()), axis=1)
    failing = table.assign(signature=sig)[sig.map(is_failure_signature)]
    return failing.groupby(list(GROUP_KEYS), observed=True).size().rename("calls").reset_index()


def _from_corpus(path: Path) -> pd.DataFrame:
    records = []
    for file, item in iter_corpus(path):
        if isinstance(item, CorpusError):
            raise UsageError(f"--baseline: {item}")
        for label, signature in item.expectations.items():
            try:
                config = AlgorithmConfig.from_label(label)
            except UsageError:
                continue
            if is_failure_signature(signature):
                records.append({"algorithm": config.algorithm, "sphere": config.sphere, "eps": config.eps, "generator": item.case.family, "signature": signature, "calls": 1})
    df = pd.DataFrame.from_records(records, columns=list(GROUP_KEYS) + ["calls"])
    return df.groupby(list(GROUP_KEYS), observed=True)["calls"].sum().reset_index() if len(df) else df


def load_baseline(path: str | os.PathLike[str]) -> pd.DataFrame:
    """Failure groups of a baseline: a run folder, a results.csv/.parquet, or a corpus folder/file.

    Raises
    ------
    UsageError
        When ``path`` is none of these, naming it.
    """
    p = Path(path)
    if not p.exists():
        raise UsageError(f"--baseline {str(path)!r}: no such file or directory")
    if p.is_dir():
        for name in RESULTS_FILES:
            if (p / name).exists():
                return load_baseline(p / name)
        if any(p.glob("*.json")):
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
    return failure_groups(table)


def compare_with_baseline(table: pd.DataFrame, baseline: pd.DataFrame) -> pd.DataFrame:
    """Every failure group of the run or the baseline, with ``state`` new / still-failing / fixed.

    ``fixed`` is only claimed for groups whose (algorithm, variant, family) the
    current run actually exercised.
    """
    current = failure_groups(table)
    keys = list(GROUP_KEYS)
    merged = current.merge(baseline[keys].drop_duplicates(), on=keys, how="outer", indicator=True)
    state = merged["_merge"].map({"left_only": "new", "both": "still-failing", "right_only": "fixed"})
    merged = merged.assign(state=state.astype(str)).drop(columns="_merge")
    exercised = set(map(tuple, table[["algorithm", "sphere", "eps", "generator"]].drop_duplicates().astype(str).values))
    keep = (merged["state"] != "fixed") | merged[["algorithm", "sphere", "eps", "generator"]].astype(str).apply(tuple, axis=1).isin(exercised)
    merged = merged[keep].fillna({"calls": 0})
    merged["calls"] = merged["calls"].astype(int)
    order = {"new": 0, "still-failing": 1, "fixed": 2}
    return merged.sort_values(by=["state", *keys], key=lambda s: s.map(order) if s.name == "state" else s).reset_index(drop=True)
