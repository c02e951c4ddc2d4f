"""Summary tables computed from a results table.

Failures are counted per stage (:class:`~hullstress.records.Stage`): ``failed``
is the algorithm's own failures; failures of the sphere method or eps set-up
(stage ``preprocess``) and internal errors of the checker (stage ``check``)
are counted in their own columns, never charged to the algorithm.
"""

from __future__ import annotations

import pandas as pd

from ..records import FAILED_STATUSES, Stage
from ..results import STATUSES

__all__ = ["FAILED_STATUSES", "STAGE_COUNT_COLUMNS", "stages", "failed_mask", "status_counts", "failure_counts"]

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


#: Columns of :func:`metamorphic_changes`.
METAMORPHIC_COLUMNS = ("config", "generator", "dim", "size", "transform", "case_id", "base_case_id",
                       "base_status", "status", "base_failed_checks", "failed_checks", "reason")


def metamorphic_changes(df: pd.DataFrame) -> pd.DataFrame:
    """Metamorphic copies whose verdict differs from their original's (``run --transform``).

    A copy (a row whose ``transform`` is set) has the same hull as the case
    it was made from, so a correct algorithm gives the same verdict on both;
    a change of status or of failed checks shows an answer that depends on
    the input's order, scale or axes.

    Examples
    --------
    >>> base = {"config": "a[sphere=off,eps=n/a]", "generator": "g", "dim": 2, "size": 8, "seed": 1,
    ...         "params": '{"k":1}', "transform": "", "case_id": "c0", "status": "pass",
    ...         "failed_checks": "", "reason": ""}
    >>> copy = dict(base, params='{"k":1,"transform":"permute-rows"}', transform="permute-rows",
    ...             case_id="c1", status="fail", failed_checks="containment", reason="1 points outside")
    >>> metamorphic_changes(pd.DataFrame([base, copy]))[["transform", "base_status", "status"]].values.tolist()
    [['permute-rows', 'pass', 'fail']]
    """
    if df.empty or "transform" not in df.columns:
        return pd.DataFrame(columns=list(METAMORPHIC_COLUMNS))
    import json

    def base_params(text: object) -> str:
        params = json.loads(str(text)) if isinstance(text, str) and text else {}
        params.pop("transform", None)
        return json.dumps(params, sort_keys=True, separators=(",", ":"))

    transform = df["transform"].fillna("").astype(str)
    keyed = df.assign(_params=df["params"].map(base_params), _transform=transform)
    keys = ["config", "generator", "dim", "size", "seed", "_params"]
    base = keyed[keyed["_transform"] == ""][keys + ["case_id", "status", "failed_checks"]]
    base = base.rename(columns={"case_id": "base_case_id", "status": "base_status",
                                "failed_checks": "base_failed_checks"})
    copies = keyed[keyed["_transform"] != ""]
    if copies.empty:
        return pd.DataFrame(columns=list(METAMORPHIC_COLUMNS))
    joined = copies.merge(base, on=keys, how="inner")
    same = (joined["status"] == joined["base_status"]) & (
        joined["failed_checks"].fillna("").astype(str) == joined["base_failed_checks"].fillna("").astype(str))
    return joined[~same].rename(columns={"_transform": "transform_name"}).assign(
        transform=lambda t: t["transform_name"])[list(METAMORPHIC_COLUMNS)].reset_index(drop=True)
