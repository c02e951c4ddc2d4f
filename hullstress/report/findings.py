"""Findings: do the seed documents' claims hold on this run's data?

The seeds claim that (1) Kenwright's sphere projection tames coplanar and
collinear inputs and (2) an epsilon scaled to the geometry's extent keeps
coplanar points on the hull.  The findings table answers with failure rates:
for each family and algorithm, the share of calls in which the algorithm
failed (fail, error, timeout, crash; ``rejected`` is acceptable behaviour and
not a failure) with sphere off vs on, and with eps scaled vs fixed.  With
sphere on the algorithm is judged on the projected points it was given; the
sphere method's own failures (stage ``preprocess``: it raised, or the correct
hull of the projected points does not map back to the input's hull) are the
column ``sphere_method``, and ``sphere_end_to_end`` is the share of sphere-on
calls that did not end in the input's hull for either reason, the measure of
claim (1).  Cells with no calls (an algorithm without ``eps``) are missing,
not zero.
"""

from __future__ import annotations

import pandas as pd

from ..records import Stage
from .tables import failed_mask

__all__ = ["findings_table", "findings_reading", "findings_markdown", "claim_families", "CLAIM_FAMILY_WORDS"]

#: A family is in the claims' scope when its name, or the module that registers
#: it (``generators.coplanar``, ``generators.collinear``), contains one of these.
CLAIM_FAMILY_WORDS = ("coplanar", "collinear")

_COLUMNS = ["family", "algorithm", "calls", "rate", "sphere_off", "sphere_on", "sphere_method", "sphere_end_to_end",
            "eps_scaled", "eps_fixed"]


def _rate(df: pd.DataFrame, *stages: Stage) -> float:
    """Share of ``df``'s calls failing at any of ``stages`` (the algorithm by default)."""
    if not len(df):
        return float("nan")
    mask = pd.Series(False, index=df.index)
    for stage in stages or (Stage.ALGORITHM,):
        mask |= failed_mask(df, stage)
    return float(mask.mean())


def findings_table(table: pd.DataFrame) -> pd.DataFrame:
    """Failure rate per family x algorithm, split by sphere (off/on) and eps (scaled/fixed).

    Parameters
    ----------
    table : DataFrame
        A results table.

    Returns
    -------
    DataFrame
        Columns ``family, algorithm, calls, rate, sphere_off, sphere_on,
        sphere_method, sphere_end_to_end, eps_scaled, eps_fixed`` (rates in
        [0, 1], NaN where no call ran).

    Examples
    --------
    >>> t = pd.DataFrame({"generator": "grid", "algorithm": "a", "sphere": ["off", "on", "off", "on"],
    ...                   "eps": ["scaled", "scaled", "fixed", "fixed"],
    ...                   "status": ["fail", "pass", "fail", "fail"],
    ...                   "stage": ["algorithm", "algorithm", "algorithm", "preprocess"]})
    >>> cols = ["sphere_off", "sphere_on", "sphere_method", "sphere_end_to_end", "eps_scaled", "eps_fixed"]
    >>> findings_table(t)[cols].iloc[0].tolist()
    [1.0, 0.0, 0.5, 0.5, 0.5, 0.5]
    """
    if not len(table):
        return pd.DataFrame(columns=_COLUMNS)
    # Only the columns needed: slicing the whole (wide, string-heavy) table per group is slow.
    algorithm_failed = failed_mask(table, Stage.ALGORITHM).to_numpy(dtype=float)
    method_failed = failed_mask(table, Stage.PREPROCESS).to_numpy(dtype=float)
    base = pd.DataFrame({
        "family": table["generator"].astype(str).to_numpy(), "algorithm": table["algorithm"].astype(str).to_numpy(),
        "sphere": table["sphere"].astype(str).to_numpy(), "eps": table["eps"].astype(str).to_numpy(),
        "failed": algorithm_failed, "method": method_failed,
        "end_to_end": ((algorithm_failed + method_failed) > 0).astype(float),
    })
    keys = ["family", "algorithm"]
    groups = base.groupby(keys, sort=True)
    out = pd.DataFrame({"calls": groups.size(), "rate": groups["failed"].mean()})
    on = base[base["sphere"] == "on"].groupby(keys, sort=True)
    out["sphere_method"] = on["method"].mean().reindex(out.index)
    out["sphere_end_to_end"] = on["end_to_end"].mean().reindex(out.index)
    for column, (field, value) in {"sphere_off": ("sphere", "off"), "sphere_on": ("sphere", "on"),
                                   "eps_scaled": ("eps", "scaled"), "eps_fixed": ("eps", "fixed")}.items():
        out[column] = base[base[field] == value].groupby(keys, sort=True)["failed"].mean().reindex(out.index)
    return out.reset_index()[_COLUMNS].astype({"calls": int})


def claim_families(families: list[str]) -> list[str]:
    """The families among ``families`` that the seeds' claims are about (coplanar, collinear inputs).

    Examples
    --------
    >>> claim_families(["coplanar-grid", "random-ball", "my-collinear-runs"])
    ['coplanar-grid', 'my-collinear-runs']
    """
    from .._registry import GENERATORS

    chosen = []
    for family in families:
        module = ""
        try:
            if family in GENERATORS:
                module = getattr(GENERATORS.get(family).func, "__module__", "") or ""
        except Exception:  # a broken generator package must not break the report
            module = ""
        text = f"{family} {module}".lower()
        if any(word in text for word in CLAIM_FAMILY_WORDS):
            chosen.append(family)
    return chosen


def _compare(f: pd.DataFrame, a: str, b: str) -> tuple[int, int, int, float, float, int]:
    both = f.dropna(subset=[a, b])
    return (int((both[b] < both[a]).sum()), int((both[b] > both[a]).sum()), int((both[b] == both[a]).sum()),
            float(both[a].mean()) if len(both) else float("nan"),
            float(both[b].mean()) if len(both) else float("nan"), len(both))


def findings_reading(findings: pd.DataFrame) -> list[str]:
    """A short, literal reading of the findings table: one sentence per claim and scope.

    Counts cells (family x algorithm) where the rate went down, up or stayed
    the same, and gives the mean rates.  "Helped" needs both more cells down
    than up and a lower mean; a mean difference under one percentage point is
    called immaterial.  No significance test is made; a comparison without
    data says so.
    """
    lines = []
    claim = findings[findings["family"].isin(claim_families(sorted(findings["family"].unique())))]
    scopes = [("degenerate families (" + ", ".join(sorted(claim["family"].unique())) + ")", claim)] if len(claim) else []
    scopes.append(("all families", findings))
    for what, a, b, label in (
        ("sphere projection", "sphere_off", "sphere_end_to_end", "off vs on, end to end"),
        ("the algorithms on the projected points", "sphere_off", "sphere_on", "input vs projected"),
        ("the scaled epsilon", "eps_fixed", "eps_scaled", "fixed vs scaled"),
    ):
        for scope, f in scopes:
            lower, higher, same, ma, mb, n = _compare(f, a, b)
            if n == 0:
                lines.append(f"{what}, {scope}: no cell ran both variants, so the claim is untested here.")
                continue
            if lower == higher == 0:
                verdict = "made no difference"
            elif abs(mb - ma) < 0.01:
                verdict = "made no material difference (under one percentage point)"
            elif lower > higher and mb < ma:
                verdict = "helped on balance"
            elif higher > lower and mb > ma:
                verdict = "hurt on balance"
            else:
                verdict = "had a mixed effect"
            lines.append(
                f"{what}, {scope}: mean failure rate {ma:.1%} ({label.split(' vs ')[0]}) vs {mb:.1%} "
                f"({label.split(' vs ')[1]}); lower in {lower}, higher in {higher}, equal in {same} of {n} "
                f"family x algorithm cells: it {verdict}."
            )
    for scope, f in scopes:
        method = f["sphere_method"].dropna()
        if len(method):
            lines.append(f"the sphere method itself, {scope}: it raised or lost the input's hull in {method.mean():.1%} "
                         f"of sphere-on calls on average (stage preprocess, not counted against the algorithms).")
    return lines


def _pct(x: float) -> str:
    return "" if pd.isna(x) else f"{x:.0%}"


def findings_markdown(findings: pd.DataFrame, reading: list[str] | None = None) -> str:
    """The findings as a Markdown section body: the reading, then the table (rates in %)."""
    reading = findings_reading(findings) if reading is None else reading
    out = [f"- {line}" for line in reading]
    out.append("")
    if findings.empty:
        out.append("_(no calls)_")
        return "\n".join(out) + "\n"
    out.append("| family | algorithm | calls | rate | sphere off | sphere on | sphere method | sphere end to end "
               "| eps scaled | eps fixed |")
    out.append("|---|---|---|---|---|---|---|---|---|---|")
    for r in findings.itertuples(index=False):
        out.append(f"| {r.family} | {r.algorithm} | {r.calls} | {_pct(r.rate)} | {_pct(r.sphere_off)} | "
                   f"{_pct(r.sphere_on)} | {_pct(r.sphere_method)} | {_pct(r.sphere_end_to_end)} | "
                   f"{_pct(r.eps_scaled)} | {_pct(r.eps_fixed)} |")
    return "\n".join(out) + "\n"
