"""Finding: Kenwright's sphere method per dimension, with its two causes counted apart.

The seed claims that projecting the surface points onto a sphere tames
coplanar and collinear input.  With sphere on, the algorithm is judged on the
projected points (stage ``algorithm``) and the method on whether the hull,
mapped back, is the input's hull (stage ``preprocess``); only the latter is
the method's finding.  Its causes are read from the columns of
:mod:`hullstress.sphere_causes`, once per **projection** (a case's sphere-on
rows share one; the scaled duplicate tolerance is preferred where a case ran
both), each over the projections where it is known:

``vertex lost``
    the surface list dropped at least one true extreme point (of the
    projections with a certified extreme set); with ``true vertices lost``,
    how many of all true vertices;
``faces change, every vertex kept``
    projecting exactly the true extreme points from the method's centroid and
    hulling them exactly does not give the input's hull, mapped back (of the
    projections where that hull is certified): the projection alone changes
    the face structure, whatever the support mapping keeps;
``faces changed, none lost``
    observed on the method's own projection: no true vertex lost, and still
    not the input's hull;
``hull kept``
    the method's own projection, hulled exactly and mapped back, is the input's hull;
``no projection``
    the method raised or declined before the algorithm ran.
"""

from __future__ import annotations

import pandas as pd

from ..records import Sphere, SphereStructure, Stage, Status
from ..tolerance import EpsPolicy
from .claim import Claim
from .slices import CONTROL_FAMILY, claim_families, duplicate_policy, percent, placement_order, ratio
from .tables import failed_mask

__all__ = ["sphere_claim", "projections"]

_KEYS = ["dim", "family", "variant", "placement", "n"]
_SAME, _CHANGED = SphereStructure.SAME.value, SphereStructure.CHANGED.value


def projections(table: pd.DataFrame) -> pd.DataFrame:
    """One row per case run with sphere on: its slicing columns and the causes' columns.

    Parameters
    ----------
    table : DataFrame
        A sliced results table (:func:`hullstress.report.slices.sliced`).

    Returns
    -------
    DataFrame
        Columns ``case_id, dim, family, variant, placement, n, projected, extreme, lost, structure,
        kept_structure``; ``projected`` is False when the method raised or declined before the call.
    """
    cols = ["case_id", *_KEYS, "projected", "extreme", "lost", "structure", "kept_structure"]
    on = table[table["sphere"] == Sphere.ON.value] if len(table) else table
    if not len(on):
        return pd.DataFrame(columns=cols)
    structure = on["sphere_structure"].astype("string").fillna("")
    kept = on["sphere_kept_structure"].astype("string").fillna("")
    rank = (structure == "").astype(int) * 2 + (duplicate_policy(on["eps"]) != EpsPolicy.SCALED.value).astype(int)
    one = on.assign(structure=structure, kept_structure=kept, _rank=rank)
    one = one.sort_values(["case_id", "_rank"], kind="stable").drop_duplicates("case_id")
    declined = (one["stage"] == Stage.PREPROCESS.value) & one["status"].isin([Status.ERROR.value, Status.REJECTED.value])
    out = one.assign(projected=~((one["structure"] == "") & declined),
                     extreme=one["sphere_extreme"], lost=one["sphere_lost_extreme"])
    return out[cols].reset_index(drop=True)


def _projection_counts(proj: pd.DataFrame, keys: list[str]) -> pd.DataFrame:
    """Per group of ``keys``: projections, and each cause with the projections where it is known."""
    p = proj.assign(
        no_projection=~proj["projected"],
        extreme_known=proj["extreme"].notna(),
        vertex_lost=proj["lost"].fillna(0) > 0,
        extreme_sum=proj["extreme"].fillna(0), lost_sum=proj["lost"].fillna(0),
        kept_known=proj["kept_structure"].isin([_SAME, _CHANGED]),
        faces_change=proj["kept_structure"] == _CHANGED,
        observed_known=proj["structure"].isin([_SAME, _CHANGED]),
        hull_kept=proj["structure"] == _SAME,
        changed_none_lost=(proj["structure"] == _CHANGED) & (proj["lost"].fillna(-1) == 0),
        none_lost=proj["lost"].fillna(-1) == 0,
    )
    measures = ["no_projection", "extreme_known", "vertex_lost", "extreme_sum", "lost_sum", "kept_known",
                "faces_change", "observed_known", "hull_kept", "none_lost", "changed_none_lost"]
    return p.groupby(keys, observed=True).agg(projections=("case_id", "size"), **{m: (m, "sum") for m in measures})


def _counts(proj: pd.DataFrame, rows: pd.DataFrame, keys: list[str]) -> pd.DataFrame:
    """:func:`_projection_counts` with the sphere-on rows' failures per stage, per group of ``keys``."""
    out = _projection_counts(proj, keys)
    work = rows[keys].copy()
    work["method_failed"] = failed_mask(rows, Stage.PREPROCESS).astype(int)
    work["algorithm_failed"] = failed_mask(rows, Stage.ALGORITHM).astype(int)
    per_row = work.groupby(keys, observed=True).agg(rows=("method_failed", "size"),
                                                    method_failed=("method_failed", "sum"),
                                                    algorithm_failed=("algorithm_failed", "sum"))
    return out.join(per_row, how="left").fillna(0).astype(int).reset_index()


def _view(counts: pd.DataFrame, keys: list[str]) -> pd.DataFrame:
    """The compact columns of a counts frame, as text."""
    c = counts
    view = c[keys].copy()
    view["projections"] = c["projections"]
    view["no projection"] = c["no_projection"]
    view["vertex lost"] = [ratio(a, b) for a, b in zip(c["vertex_lost"], c["extreme_known"])]
    view["true vertices lost"] = [f"{a}/{b} ({percent(a, b)})" if b else "-"
                                  for a, b in zip(c["lost_sum"], c["extreme_sum"])]
    view["faces change, every vertex kept"] = [ratio(a, b) for a, b in zip(c["faces_change"], c["kept_known"])]
    view["faces changed, none lost"] = [ratio(a, b) for a, b in zip(c["changed_none_lost"], c["none_lost"])]
    view["hull kept"] = [ratio(a, b) for a, b in zip(c["hull_kept"], c["observed_known"])]
    view["method failed (rows)"] = [ratio(f, n) for f, n in zip(c["method_failed"], c["rows"])]
    return view


def _groups(frame: pd.DataFrame, degenerate: set[str]) -> pd.Series:
    return frame["family"].map(lambda f: "uniform (control)" if f == CONTROL_FAMILY
                               else "degenerate families" if f in degenerate else "other families")


def _why(proj: pd.DataFrame, dim: int, what: str) -> str:
    """One sentence: the two causes, counted apart, on ``proj`` in dimension ``dim``."""
    if not len(proj):
        return ""
    c = _projection_counts(proj.assign(_all=0), ["_all"]).astype(int).iloc[0]
    known = proj[proj["extreme"].fillna(0) > 0]
    shares = (known["lost"] / known["extreme"]).astype(float)
    spread = f"; {shares.min():.0%} to {shares.max():.0%} per projection" if len(shares) else ""
    sizes = ", ".join(str(int(n)) for n in sorted(proj["n"].dropna().unique()))
    return (f"{dim}D, {what} ({c['projections']} projections, n = {sizes or '-'}): (a) vertex loss: the support "
            f"mapping dropped a true vertex in {ratio(c['vertex_lost'], c['extreme_known'])} "
            f"({percent(c['vertex_lost'], c['extreme_known'])}), {c['lost_sum']} of {c['extreme_sum']} true "
            f"vertices ({percent(c['lost_sum'], c['extreme_sum'])}{spread}); (b) face structure: projecting "
            f"exactly the true vertices and hulling them exactly gives, mapped back, a different hull in "
            f"{ratio(c['faces_change'], c['kept_known'])} ({percent(c['faces_change'], c['kept_known'])}); "
            f"where the method itself lost no vertex, its hull still changed in "
            f"{ratio(c['changed_none_lost'], c['none_lost'])}.")


def sphere_claim(table: pd.DataFrame) -> Claim:
    """The sphere-method finding of a sliced results table."""
    proj = projections(table)
    rows = table[table["sphere"] == Sphere.ON.value]
    degenerate = set(claim_families(sorted(table["generator"].unique()))) if len(table) else set()
    scope = ("rows with sphere on; the method's verdict (stage preprocess) and its causes, one projection per "
             "case; the algorithms' own failures on the projected points (stage algorithm) are theirs, not the "
             "method's, and are counted apart.")
    if not len(proj):
        return Claim("sphere-method", "The sphere method, per dimension", scope,
                     ("No row ran with sphere on: the claim is untested here.",), ())
    proj = proj.assign(group=_groups(proj, degenerate))
    rows = rows.assign(group=_groups(rows, degenerate))
    detail = _counts(proj, rows, _KEYS)
    reading, why = [], []
    for dim in sorted(proj["dim"].unique()):
        r = rows[rows["dim"] == dim]
        u = r[r["family"] == CONTROL_FAMILY]
        m, a = int(failed_mask(r, Stage.PREPROCESS).sum()), int(failed_mask(r, Stage.ALGORITHM).sum())
        mu = int(failed_mask(u, Stage.PREPROCESS).sum())
        reading.append(f"{dim}D: the sphere method failed (stage preprocess) in {ratio(m, len(r))} sphere-on rows "
                       f"({percent(m, len(r))}), on uniform clouds in {ratio(mu, len(u))} ({percent(mu, len(u))}): "
                       f"it raised, or the hull it mapped back was not the input's; the algorithms failed on the "
                       f"projected points (stage algorithm, their own failures) in {ratio(a, len(r))}.")
        p = proj[proj["dim"] == dim]
        for what, sub in (("uniform clouds", p[p["family"] == CONTROL_FAMILY]), ("all families", p)):
            line = _why(sub, int(dim), what)
            if line:
                why.append(line)
    by_group = _counts(proj, rows, ["dim", "group"])
    control = proj["family"] == CONTROL_FAMILY
    control_rows = rows[rows["family"] == CONTROL_FAMILY]
    by_size = _counts(proj[control], control_rows, ["dim", "n"])
    by_variant = _counts(proj[control], control_rows, ["dim", "variant"])
    placed = table.loc[table["placed"], "case_id"].unique() if "placed" in table else []
    pp = proj[proj["case_id"].isin(placed)]
    by_place = _counts(pp, rows[rows["case_id"].isin(placed)], ["dim", "placement"])
    order = {p: i for i, p in enumerate(placement_order(by_place["placement"].tolist()))}
    by_place = by_place.sort_values(["dim", "placement"], key=lambda s: s.map(order) if s.name == "placement" else s)
    tables = (("By dimension and family group (projections; the method's verdict counted in rows)",
               _view(by_group, ["dim", "group"])),
              ("Uniform clouds by size", _view(by_size, ["dim", "n"])),
              ("Uniform clouds by variant", _view(by_variant, ["dim", "variant"])),
              ("Families that place their points (scale x, offset +), by placement",
               _view(by_place, ["dim", "placement"])))
    return Claim("sphere-method", "The sphere method, per dimension: vertex loss and face-structure change", scope,
                 tuple(reading), tuple(why), tables, detail)
