"""Findings: do the seed documents' claims hold on this run's data?

The seeds claim that (1) Kenwright's sphere projection tames coplanar and
collinear inputs and (2) an epsilon scaled to the geometry's extent keeps
coplanar points on the hull.  The findings table answers with failure rates:
for each family and algorithm, the share of failed calls (fail, error,
timeout, crash; ``rejected`` is acceptable behaviour and not a failure) with
sphere off vs on, and with eps scaled vs fixed.  Cells with no calls (an
algorithm without ``eps``) are missing, not zero.
"""

from __future__ import annotations

import pandas as pd

from .tables import FAILED_STATUSES

__all__ = ["findings_table", "findings_reading", "findings_markdown", "claim_families", "CLAIM_FAMILY_WORDS"]

#: A family is in the claims' scope when its name, or the module that registers
#: it (``generators.coplanar``, ``generators.collinear``), contains one of these.
CLAIM_FAMILY_WORDS = ("coplanar", "collinear")

_COLUMNS = ["family", "algorithm", "calls", "rate", "sphere_off", "sphere_on", "eps_scaled", "eps_fixed"]


def _rate(df: pd.DataFrame) -> float:
    return float(df["status"].isin(FAILED_STATUSES).mean()) if len(df) else float("nan")


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
        eps_scaled, eps_fixed`` (rates in [0, 1], NaN where no call ran).

    Examples
    --------
    >>> t = pd.DataFrame({"generator": "grid", "algorithm": "a", "sphere": ["off", "on", "off", "on"],
    ...                   "eps": ["scaled", "scaled", "fixed", "fixed"],
    ...                   "status": ["fail", "pass", "fail", "rejected"]})
    >>> findings_table(t)[["sphere_off", "sphere_on", "eps_scaled", "eps_fixed"]].iloc[0].tolist()
    [1.0, 0.0, 0.5, 0.5]
    """
    if not len(table):
        return pd.DataFrame(columns=_COLUMNS)
    # One grouped pass per split (rather than filtering every family x algorithm cell): the quick
    # profile has several hundred cells.
    keys = ["generator", "algorithm"]
    frame = table[keys + ["sphere", "eps"]].assign(failed=table["status"].isin(FAILED_STATUSES).astype(float))
    grouped = frame.groupby(keys, sort=True, observed=True)["failed"]
    out = pd.DataFrame({"calls": grouped.size(), "rate": grouped.mean()})
    for column, split in (("sphere", ("off", "on")), ("eps", ("scaled", "fixed"))):
        rates = frame.groupby(keys + [column], observed=True)["failed"].mean().unstack(column)
        for value in split:
            out[f"{column}_{value}"] = rates[value] if value in rates.columns else float("nan")
    out = out.reset_index().rename(columns={"generator": "family"})
    out["calls"] = out["calls"].astype(int)
    return out[_COLUMNS].reset_index(drop=True)



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
        ("sphere projection", "sphere_off", "sphere_on", "off vs on"),
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
    out.append("| family | algorithm | calls | rate | sphere off | sphere on | eps scaled | eps fixed |")
    out.append("|---|---|---|---|---|---|---|---|")
    for r in findings.itertuples(index=False):
        out.append(f"| {r.family} | {r.algorithm} | {r.calls} | {_pct(r.rate)} | {_pct(r.sphere_off)} | "
                   f"{_pct(r.sphere_on)} | {_pct(r.eps_scaled)} | {_pct(r.eps_fixed)} |")
    return "\n".join(out) + "\n"
