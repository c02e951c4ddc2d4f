"""Finding: the scaled vs the fixed epsilon, across scales and offsets, per algorithm that takes eps.

The gift-wrapping seed scales its tolerance by the input's extent; the
``fixed`` policy is the same number without that factor.  The two can only
differ where the extent is far from 1, so the claim is read on the families
that place their points (parameters ``scale`` and ``offset``: ``uniform`` at
x1, ``scaled``, ``offset``, ``compose``), with sphere off: the projection onto
a unit sphere removes the scale before the algorithm sees it.  Failures are
the algorithm's own (stage ``algorithm``).  The cause is measured from the
``eps_value`` column: the tolerance relative to the size of the coordinates
(the placement's scale or offset), against the 1.1e-16 relative rounding of
one coordinate.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..tolerance import MACHINE_EPSILON, EpsPolicy
from .claim import Claim
from .slices import CONTROL_FAMILY, failure_counts_by, placement_order, ratio
from ..records import Sphere

__all__ = ["eps_claim", "MODERATE_SCALES"]

#: The scales where real data lives and a fixed tolerance is the usual bug (x1 .. x1e12).
MODERATE_SCALES = (1.0, 1e12)
_FIXED, _SCALED = EpsPolicy.FIXED.value, EpsPolicy.SCALED.value
_KEYS = ["algorithm", "dim", "family", "variant", "placement", "n"]


def _rows(table: pd.DataFrame) -> pd.DataFrame:
    if not len(table):
        return table
    return table[(table["sphere"] == Sphere.OFF.value) & table["eps"].isin([_FIXED, _SCALED]) & table["placed"]]


def _detail(rows: pd.DataFrame) -> pd.DataFrame:
    counts = failure_counts_by(rows, _KEYS + ["eps"])
    eps = rows.groupby(_KEYS + ["eps"], observed=True)["eps_value"].median().rename("eps_value").reset_index()
    counts = counts.merge(eps, on=_KEYS + ["eps"], how="left")
    wide = counts.pivot_table(index=_KEYS, columns="eps", values=["failed", "calls", "unjudged", "eps_value"],
                              aggfunc="first", observed=True)
    wide.columns = [f"{policy}_{what}" for what, policy in wide.columns]
    for policy in (_FIXED, _SCALED):
        for what in ("failed", "calls", "unjudged"):
            col = f"{policy}_{what}"
            wide[col] = wide[col].fillna(0).astype(int) if col in wide else 0
        if f"{policy}_eps_value" not in wide:
            wide[f"{policy}_eps_value"] = np.nan
    return wide.reset_index()[_KEYS + [f"{p}_{w}" for p in (_FIXED, _SCALED)
                                        for w in ("failed", "calls", "unjudged", "eps_value")]]


def _pair(sub: pd.DataFrame) -> str:
    """``"fixed F/N vs scaled S/N"`` summed over ``sub``, shortened to ``F/N vs S/N``."""
    return (f"{ratio(sub[f'{_FIXED}_failed'].sum(), sub[f'{_FIXED}_calls'].sum())} vs "
            f"{ratio(sub[f'{_SCALED}_failed'].sum(), sub[f'{_SCALED}_calls'].sum())}")


def _matrix(detail: pd.DataFrame, placements: list[str]) -> pd.DataFrame:
    """Rows algorithm x dim x family (those with a row at one of ``placements``), a column per placement,
    cells ``fixed F/N vs scaled S/N``."""
    part = detail[detail["placement"].isin(placements)]
    counts = [f"{policy}_{what}" for policy in (_FIXED, _SCALED) for what in ("failed", "calls")]
    # One grouped sum for every cell (a cell per filter of the rows costs seconds on a quick run's table).
    sums = part.groupby(["algorithm", "dim", "family", "placement"], sort=True, observed=True)[counts].sum()
    cells: dict[tuple, dict[str, str]] = {}
    for (alg, dim, family, p), (fixed_failed, fixed_calls, scaled_failed, scaled_calls) in zip(
            sums.index, sums.itertuples(index=False)):
        cells.setdefault((alg, dim, family), {})[p] = (f"{ratio(fixed_failed, fixed_calls)} vs "
                                                      f"{ratio(scaled_failed, scaled_calls)}")
    out = [{"algorithm": alg, "dim": dim, "family": family, **{p: row.get(p, "-") for p in placements}}
           for (alg, dim, family), row in cells.items()]
    return pd.DataFrame.from_records(out, columns=["algorithm", "dim", "family", *placements])


def _differences(sub: pd.DataFrame, placements: list[str]) -> list[str]:
    """``family placement F/N vs S/N`` for every cell of one algorithm where the two policies' counts differ."""
    cells = []
    for (family, p), cell in sub.groupby(["family", "placement"], observed=True):
        fixed, scaled = int(cell[f"{_FIXED}_failed"].sum()), int(cell[f"{_SCALED}_failed"].sum())
        if fixed != scaled:
            cells.append((placements.index(p), family, f"{family} {p} {_pair(cell)}"))
    return [text for _, _, text in sorted(cells)]


def _magnitude(detail: pd.DataFrame) -> pd.Series:
    """The size of the coordinates a placement gives a unit shape: its offset, else its scale."""
    return detail["placement"].map(lambda p: float(p[1:]))


def _why(detail: pd.DataFrame, moderate: list[str], offsets: list[str]) -> list[str]:
    """The tolerance relative to the coordinates, measured from ``eps_value``, per placement."""
    if not len(detail):
        return []
    d = detail.assign(_mag=_magnitude(detail))
    parts = []
    for p in moderate + offsets:
        sub = d[d["placement"] == p]
        mag = float(sub["_mag"].iloc[0])
        fixed, scaled = sub[f"{_FIXED}_eps_value"].median(), sub[f"{_SCALED}_eps_value"].median()
        if pd.isna(fixed) or pd.isna(scaled) or mag <= 0:
            continue
        parts.append(f"{p}: fixed {fixed / mag:.1e}, scaled {scaled / mag:.1e}")
    if not parts:
        return []
    return [f"the tolerance measured on the rows (median eps_value divided by the size of the coordinates, "
            f"against the {MACHINE_EPSILON / 2:.1e} relative rounding of one coordinate): " + "; ".join(parts)
            + ". A tolerance far below the rounding of the coordinates cannot absorb a single rounding error; "
            "the scaled one follows the extent of the shape (the spread of distances from the origin), so it "
            "keeps pace with a scale but not with an offset, where the shape stays small."]


def eps_claim(table: pd.DataFrame) -> Claim:
    """The eps-policy finding of a sliced results table."""
    rows = _rows(table)
    scope = ("sphere off, eps scaled vs fixed, algorithms that take eps; the families on the scale axis (rows at "
             f"more than one placement, x scale or + offset) and the `{CONTROL_FAMILY}` control at x1; failures "
             "of the algorithm itself (stage algorithm); cells are `fixed failed/calls vs scaled failed/calls`.")
    title = "The scaled vs the fixed epsilon, across scales"
    if not len(rows):
        return Claim("eps-policy", title, scope, ("No sphere-off row on the scale axis ran an eps policy: "
                                                  "the claim is untested here.",), ())
    detail = _detail(rows)
    placements = placement_order(detail["placement"].unique().tolist())
    lo, hi = MODERATE_SCALES
    scales = [p for p in placements if p.startswith("x")]
    moderate = [p for p in scales if lo <= float(p[1:]) <= hi]
    offsets = [p for p in placements if p.startswith("+")]
    extreme = [p for p in scales if p not in moderate]
    reading, same = [], []
    for (alg, dim), sub in detail.groupby(["algorithm", "dim"], sort=True, observed=True):
        differ = _differences(sub, placements)
        if differ:
            cells = f"{len(differ)} cell" + ("s" if len(differ) != 1 else "")
            reading.append(f"{alg} ({dim}D): the policies differ in {cells} (fixed vs scaled): " + "; ".join(differ) + ".")
        else:
            same.append(f"{alg} ({int(sub[f'{_FIXED}_calls'].sum())} calls per policy)")
    if same:
        reading.append("Identical failure counts under both policies in every cell: " + ", ".join(same) + ".")
    tables = tuple((caption, _matrix(detail, group)) for caption, group in (
        ("Moderate scales (x1 to x1e12)", moderate), ("Offsets", offsets), ("Extreme scales", extreme)) if group)
    return Claim("eps-policy", title, scope, tuple(reading), tuple(_why(detail, moderate, offsets)), tables, detail)
