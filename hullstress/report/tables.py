"""Summary tables computed from a results table.

Failures are counted per stage (:class:`~hullstress.records.Stage`): ``failed``
is the algorithm's own failures; failures of the sphere method or eps set-up
(stage ``preprocess``) and internal errors of the checker (stage ``check``)
are counted in their own columns, never charged to the algorithm.
"""

from __future__ import annotations

import pandas as pd

from ..records import Stage
from ..results import STATUSES

__all__ = ["FAILED_STATUSES", "STAGE_COUNT_COLUMNS", "stages", "failed_mask", "status_counts", "failure_counts"]

#: Statuses that count as a failure of the code under test.
FAILED_STATUSES = ("fail", "error", "timeout", "crash")
#: Failure counts per stage, as columns of :func:`status_counts`.
STAGE_COUNT_COLUMNS = {Stage.ALGORITHM: "failed", Stage.PREPROCESS: "method_failed", Stage.CHECK: "internal_errors"}


def stages(df: pd.DataFrame) -> pd.Series:
    """The stage of every row (``algorithm`` for tables from before the stage column)."""
    if "stage" not in df.columns:
        return pd.Series(Stage.ALGORITHM.value, index=df.index)
    return df["stage"].astype("string").fillna(Stage.ALGORITHM.value).replace("", Stage.ALGORITHM.value)


def failed_mask(df: pd.DataFrame, stage: Stage = Stage.ALGORITHM) -> pd.Series:
    """Rows that are failures (fail, error, timeout, crash) of ``stage``.

    Examples
    --------
    >>> t = pd.DataFrame({"status": ["fail", "fail", "pass"], "stage": ["algorithm", "preprocess", "algorithm"]})
    >>> failed_mask(t).tolist(), failed_mask(t, Stage.PREPROCESS).tolist()
    ([True, False, False], [False, True, False])
    """
    return (df["status"].isin(FAILED_STATUSES) & (stages(df) == stage.value)).astype(bool)


def status_counts(df: pd.DataFrame, by: list[str]) -> pd.DataFrame:
    """Calls per status for each group of ``by``, with the failures per stage and ``failure_rate``.

    ``failed`` counts the algorithm's failures and ``failure_rate`` is
    ``failed / calls``; ``method_failed`` (sphere method, eps set-up) and
    ``internal_errors`` (checker) count the other stages' failures.
    """
    counts = (
        df.groupby(by + ["status"], dropna=False, observed=True)
        .size()
        .unstack("status", fill_value=0)
        .reindex(columns=list(STATUSES), fill_value=0)
    )
    counts["calls"] = counts[list(STATUSES)].sum(axis=1)
    keys = [df[c] for c in by]
    for stage, column in STAGE_COUNT_COLUMNS.items():
        per_group = failed_mask(df, stage).groupby(keys, dropna=False, observed=True).sum()
        counts[column] = per_group.reindex(counts.index, fill_value=0).astype(int)
    counts["failure_rate"] = (counts["failed"] / counts["calls"]).round(3)
    return counts.reset_index()


def failure_counts(df: pd.DataFrame) -> pd.DataFrame:
    """Failure counts by algorithm x variant x family (groups with a failure at any stage), worst first."""
    table = status_counts(df, ["algorithm", "sphere", "eps", "generator"])
    table = table[table[list(STAGE_COUNT_COLUMNS.values())].sum(axis=1) > 0]
    return table.sort_values(["failed", "method_failed", "algorithm", "sphere", "eps", "generator"],
                             ascending=[False, False, True, True, True, True]).reset_index(drop=True)
