"""Summary tables computed from a results table."""

from __future__ import annotations

import pandas as pd

from ..results import STATUSES

__all__ = ["FAILED_STATUSES", "status_counts", "failure_counts"]

#: Statuses that count as a failure of the code under test.
FAILED_STATUSES = ("fail", "error", "timeout", "crash")


def status_counts(df: pd.DataFrame, by: list[str]) -> pd.DataFrame:
    """Calls per status for each group of ``by``, with ``calls``, ``failed`` and ``failure_rate``."""
    counts = (
        df.groupby(by + ["status"], dropna=False, observed=True)
        .size()
        .unstack("status", fill_value=0)
        .reindex(columns=list(STATUSES), fill_value=0)
    )
    counts["calls"] = counts[list(STATUSES)].sum(axis=1)
    counts["failed"] = counts[list(FAILED_STATUSES)].sum(axis=1)
    counts["failure_rate"] = (counts["failed"] / counts["calls"]).round(3)
    return counts.reset_index()


def failure_counts(df: pd.DataFrame) -> pd.DataFrame:
    """Failure counts by algorithm x variant x family (only groups with a failure), worst first."""
    table = status_counts(df, ["algorithm", "sphere", "eps", "generator"])
    table = table[table["failed"] > 0]
    return table.sort_values(["failed", "algorithm", "sphere", "eps", "generator"], ascending=[False, True, True, True, True]).reset_index(drop=True)
