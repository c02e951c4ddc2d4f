"""Findings about the control family: the uniform family's failures by variant and size, and
each algorithm's failures on the degenerate families against that control.

Uniform random points are the control group: an algorithm that fails there is
broken outright, so a failure on them needs its scope (which variant: a plain
cloud, or one with a cube's corners added; which size).  The degenerate
families are the ones the seeds' claims are about
(:func:`~hullstress.report.slices.claim_families`).  Only the algorithm's own
failures count (stage ``algorithm``): with sphere on, that is the algorithm on
the projected points, never the sphere method's loss.
"""

from __future__ import annotations

import pandas as pd

from ..config import NO_EPS
from ..tolerance import EpsPolicy
from .claim import Claim
from .slices import CONTROL_FAMILY, claim_families, failure_counts_by, failure_reasons, percent, ratio
from ..records import Sphere

__all__ = ["uniform_claim", "degenerate_claim"]

_POLICIES = (EpsPolicy.FIXED.value, EpsPolicy.SCALED.value)


def _cell(sub: pd.DataFrame) -> str:
    """``F/N`` per eps policy present: ``fixed F/N · scaled S/N``, or ``F/N`` without eps."""
    parts = []
    for eps in (*_POLICIES, NO_EPS):
        part = sub[sub["eps"] == eps]
        if len(part):
            text = ratio(part["failed"].sum(), part["calls"].sum())
            parts.append(text if eps == NO_EPS else f"{eps} {text}")
    return " · ".join(parts) if parts else "-"


def _total(sub: pd.DataFrame) -> str:
    failed, calls = int(sub["failed"].sum()), int(sub["calls"].sum())
    return f"{ratio(failed, calls)} ({percent(failed, calls)})" if calls else "-"


def _end_to_end(sub: pd.DataFrame) -> str:
    """Failures of the algorithm or of the sphere method, over every row but internal errors."""
    failed = int(sub["failed"].sum() + sub["method_failed"].sum())
    rows = int(sub["calls"].sum() + sub["unjudged"].sum() - sub["internal"].sum())
    return f"{ratio(failed, rows)} ({percent(failed, rows)})" if rows else "-"


def uniform_claim(table: pd.DataFrame) -> Claim:
    """The uniform family's failures per algorithm, split by variant, size and eps policy."""
    scope = (f"the `{CONTROL_FAMILY}` family; failures of the algorithm itself (stage algorithm); the table with "
             "sphere off, cells `failed/calls` per eps policy.")
    title = "Failures on uniform clouds, by variant and size"
    rows = table[table["generator"] == CONTROL_FAMILY] if len(table) else table
    if not len(rows):
        return Claim("uniform-variants", title, scope, (f"No `{CONTROL_FAMILY}` row ran: the claim is untested here.",), ())
    detail = failure_counts_by(rows, ["algorithm", "dim", "variant", "n", "sphere", "eps"])
    off = detail[detail["sphere"] == Sphere.OFF.value]
    on = detail[detail["sphere"] == Sphere.ON.value]
    failing = sorted(off.loc[off["failed"] > 0, "algorithm"].unique())
    clean = sorted(set(off["algorithm"]) - set(failing))
    sizes = sorted(int(n) for n in off["n"].dropna().unique())
    reading, why, matrix = [], [], []
    for alg in failing:
        sub = off[off["algorithm"] == alg]
        dim = int(sub["dim"].iloc[0])
        by_variant = "; ".join(f"{v} {_cell(sub[sub['variant'] == v])}" for v in sorted(sub["variant"].unique()))
        by_size = "; ".join(f"n={n} {_cell(sub[sub['n'] == n])}" for n in sizes if (sub["n"] == n).any())
        reading.append(f"{alg} ({dim}D), sphere off: {_total(sub)} failed; by variant: {by_variant}; by size: "
                       f"{by_size}.")
        raw = rows[(rows["algorithm"] == alg) & (rows["sphere"] == Sphere.OFF.value)]
        why.append(f"{alg}: {failure_reasons(raw)} (failed checks, or error type, of the failing calls).")
        for v in sorted(sub["variant"].unique()):
            rec: dict[str, object] = {"algorithm": alg, "variant": v}
            for n in sizes:
                part = sub[(sub["variant"] == v) & (sub["n"] == n)]
                rec[f"n={n}"] = _cell(part) if len(part) else "-"
            matrix.append(rec)
    if clean:
        calls = int(off[off["algorithm"].isin(clean)]["calls"].sum())
        reading.append(f"No failure with sphere off ({calls} calls): {', '.join(clean)}.")
    if len(on):
        per = [f"{alg} {_total(on[on['algorithm'] == alg])}" for alg in sorted(on["algorithm"].unique())
               if on.loc[on["algorithm"] == alg, "failed"].sum()]
        reading.append("With sphere on, the algorithms' own failures on the projected points: "
                       + ("; ".join(per) if per else "none") + ".")
    columns = ["algorithm", "variant", *(f"n={n}" for n in sizes)]
    tables = (("Sphere off, algorithms with a failure", pd.DataFrame.from_records(matrix, columns=columns)),)
    return Claim("uniform-variants", title, scope, tuple(reading), tuple(why), tables, detail)


def degenerate_claim(table: pd.DataFrame) -> Claim:
    """Per algorithm and dimension: failures on the degenerate families against the uniform control."""
    families = claim_families(sorted(table["generator"].unique())) if len(table) else []
    scope = ("the degenerate families (" + (", ".join(families) or "none in this run") + f") and the "
             f"`{CONTROL_FAMILY}` control; failures of the algorithm itself (stage algorithm): with sphere on, "
             "the algorithm on the projected points; the end-to-end column adds the sphere method's failures "
             "(stage preprocess), which are the method's, not the algorithm's.")
    title = "Degenerate families against the uniform control, per algorithm"
    if not len(table):
        return Claim("degenerate-vs-control", title, scope, ("No rows: the claim is untested here.",), ())
    rows = table[table["generator"].isin([*families, CONTROL_FAMILY])]
    kind = rows["generator"].map(lambda f: "uniform" if f == CONTROL_FAMILY else "degenerate")
    rows = rows.assign(kind=kind)
    detail = failure_counts_by(rows, ["algorithm", "dim", "kind", "generator", "variant", "n", "sphere", "eps"])
    summary, by_size, reading, why = [], [], [], []
    sizes = sorted(int(n) for n in detail["n"].dropna().unique())
    for (dim, alg), sub in detail.groupby(["dim", "algorithm"], sort=True, observed=True):
        rec: dict[str, object] = {"dim": dim, "algorithm": alg}
        for k in ("degenerate", "uniform"):
            off, on = (sub[(sub["kind"] == k) & (sub["sphere"] == s)] for s in (Sphere.OFF.value, Sphere.ON.value))
            rec[f"{k}, sphere off"] = _total(off) if len(off) else "-"
            rec[f"{k}, sphere on"] = _total(on) if len(on) else "-"
            rec[f"{k}, sphere on, end to end"] = _end_to_end(on) if len(on) else "-"
        summary.append(rec)
        deg = sub[(sub["kind"] == "degenerate") & (sub["sphere"] == Sphere.OFF.value)]
        size_rec: dict[str, object] = {"dim": dim, "algorithm": alg}
        for n in sizes:
            part = deg[deg["n"] == n]
            size_rec[f"n={n}"] = _total(part) if len(part) else "-"
        by_size.append(size_rec)
        raw = rows[(rows["algorithm"] == alg) & (rows["kind"] == "degenerate") & (rows["sphere"] == Sphere.OFF.value)]
        reasons = failure_reasons(raw)
        if reasons:
            why.append(f"{alg} on degenerate families, sphere off: {reasons}.")
    frame = pd.DataFrame.from_records(summary)
    for dim in sorted(frame["dim"].unique()) if len(frame) else []:
        part = frame[frame["dim"] == dim]
        cells = [f"{r['algorithm']} {r['degenerate, sphere off']} vs {r['uniform, sphere off']}"
                 for _, r in part.iterrows()]
        reading.append(f"{dim}D, sphere off, degenerate vs uniform: " + "; ".join(cells) + ".")
    tables = (("Failed/calls by family kind and sphere (sphere on: the algorithm on the projected points; end to "
               "end: the algorithm or the sphere method failed, the input's hull was not returned)", frame),
              ("Degenerate families, sphere off, by size", pd.DataFrame.from_records(by_size)))
    return Claim("degenerate-vs-control", title, scope, tuple(reading), tuple(why), tables, detail)
