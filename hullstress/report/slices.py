"""How the findings slice a results table: variants, placement (scale and offset), sizes, counts.

Every claim of :mod:`hullstress.report.findings` splits its numbers the same
way, so the splits live here once:

* **variant**: the generator parameters that differ between the family's
  rows *in this table* (``shape=cube add=cube``), so a label says what sets
  the variant apart and nothing else;
* **placement**: where a family puts its points, read from the parameters
  named ``scale`` and ``offset`` (the convention of ``uniform``, ``scaled``,
  ``offset``, ``compose``, ``collinear-line``): ``x1e6`` for a unit shape
  scaled by 1e6, ``+1e6`` for one moved by 1e6 (an offset takes precedence:
  the coordinates are then about the offset's size whatever the scale); a
  family is *placed* (on the scale axis) when its rows sit at more than one
  placement, and the control family always is, at x1;
* **n**: the requested size (``size``), or the point count of fixed-size cases;
* counts as ``failed/calls``, never a bare percentage.
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence

import numpy as np
import pandas as pd

from ..config import NO_EPS, sphere_duplicate_policy
from ..records import CONTRACT_REASON, Stage, Status
from .tables import failed_mask, stages

__all__ = [
    "CONTROL_FAMILY",
    "PLACEMENT_PARAMS",
    "sliced",
    "placement_order",
    "number_label",
    "ratio",
    "percent",
    "failure_counts_by",
    "judged_mask",
    "failure_reasons",
    "duplicate_policy",
    "claim_families",
    "CLAIM_FAMILY_WORDS",
]

#: The control family: uniform random points, which every algorithm must hull.
CONTROL_FAMILY = "uniform"
#: A family is degenerate in the seeds' sense (their claims are about it) when its name, or the
#: module that registers it (``generators.coplanar``, ``generators.collinear``), contains one of these.
CLAIM_FAMILY_WORDS = ("coplanar", "collinear")
#: Parameters that place a family's points: (scale, offset) with defaults 1 and 0.
PLACEMENT_PARAMS = ("scale", "offset")


def _params(text: str) -> dict:
    try:
        value = json.loads(text) if text else {}
    except (TypeError, ValueError):  # a points file's or corpus case's free-form params
        return {}
    return value if isinstance(value, dict) else {}


def _number(value: object, default: float) -> float:
    try:
        out = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        return default
    return out if math.isfinite(out) else default


def number_label(x: float) -> str:
    """A short exact-enough label: ``1e6``, ``5e5``, ``1000`` stays ``1e3``, ``0.01``, ``1``.

    Examples
    --------
    >>> [number_label(v) for v in (1.0, 1000.0, 1e6, 5e5, 0.01, 1e-6, 1e150, 1.7976931348623157e308)]
    ['1', '1e3', '1e6', '5e5', '0.01', '1e-6', '1e150', '1.7976931348623157e308']
    """
    if x != 0 and (abs(x) >= 1e3 or abs(x) < 1e-2):
        mantissa, exponent = np.format_float_scientific(x, unique=True, trim="-").split("e")
        return f"{mantissa}e{int(exponent)}"
    return f"{x:g}"


def _placement(params: dict) -> tuple[str, float, float]:
    scale_key, offset_key = PLACEMENT_PARAMS
    scale = _number(params.get(scale_key, 1.0), 1.0)
    offset = _number(params.get(offset_key, 0.0), 0.0)
    return (f"+{number_label(offset)}" if offset > 0 else f"x{number_label(scale)}"), scale, offset


def _variant_labels(df: pd.DataFrame, parsed: dict[str, dict]) -> pd.Series:
    """Per row, the parameters that differ between rows of its family (``"-"`` for a family of one variant)."""
    labels = pd.Series("-", index=df.index, dtype=object)
    for _, rows in df.groupby("generator", sort=False, observed=True):
        variants = [parsed[p] for p in rows["params"].unique()]
        keys = sorted({k for v in variants for k in v})
        varying = [k for k in keys if len({json.dumps(v.get(k), sort_keys=True, default=str) for v in variants}) > 1]
        if not varying:
            continue
        text = {p: " ".join(f"{k}={parsed[p].get(k)}" for k in varying) for p in rows["params"].unique()}
        labels.loc[rows.index] = rows["params"].map(text)
    return labels


def sliced(table: pd.DataFrame) -> pd.DataFrame:
    """``table`` with the slicing columns added: ``family`` (the generator), ``variant``, ``placement``,
    ``scale``, ``offset``, ``placed`` (the family is on the scale axis: its rows sit at more than one
    placement, or it is the control family) and ``n``.

    Examples
    --------
    >>> t = pd.DataFrame({"generator": ["uniform", "uniform", "offset"],
    ...                   "params": ['{"add":"none","scale":1.0}', '{"add":"cube","scale":1.0}', '{"offset":1e6}'],
    ...                   "size": [16, 16, 64], "n_points": [16, 16, 64]})
    >>> sliced(t)[["variant", "placement", "n"]].values.tolist()
    [['add=none', 'x1', 16], ['add=cube', 'x1', 16], ['-', '+1e6', 64]]
    """
    out = table.copy()
    out["family"] = out["generator"]
    params = out["params"].astype("string").fillna("") if "params" in out else pd.Series("", index=out.index)
    out["params"] = params
    parsed = {p: _params(p) for p in params.unique()}
    placed = {p: _placement(v) for p, v in parsed.items()}
    out["variant"] = _variant_labels(out, parsed) if len(out) else pd.Series(dtype=object)
    out["placement"] = params.map(lambda p: placed[p][0])
    out["scale"] = params.map(lambda p: placed[p][1]).astype("float64")
    out["offset"] = params.map(lambda p: placed[p][2]).astype("float64")
    # A family is on the scale axis when its rows in this table sit at more than one placement, or
    # it is the control (uniform points at x1, the baseline every other placement is read against).
    varying = out.groupby("family", observed=True)["placement"].transform("nunique") > 1 if len(out) else False
    out["placed"] = varying | (out["family"] == CONTROL_FAMILY)
    size = pd.to_numeric(out["size"], errors="coerce") if "size" in out else pd.Series(pd.NA, index=out.index)
    points = pd.to_numeric(out["n_points"], errors="coerce") if "n_points" in out else size
    out["n"] = size.fillna(points).astype("Int64")
    return out


def placement_order(labels: Sequence[str]) -> list[str]:
    """Placement labels in reading order: every scale by size, then every offset by size.

    Examples
    --------
    >>> placement_order(["+1e6", "x1e12", "x1", "x1e3", "x1e-300"])
    ['x1e-300', 'x1', 'x1e3', 'x1e12', '+1e6']
    """
    return sorted(set(labels), key=lambda s: (s.startswith("+"), float(s[1:])))


def duplicate_policy(eps: pd.Series) -> pd.Series:
    """The duplicate tolerance the sphere method used on each row: the row's eps policy, or scaled without one."""
    return eps.astype("string").fillna(NO_EPS).map(sphere_duplicate_policy)


def ratio(failed: int, calls: int) -> str:
    """``"failed/calls"``; ``"-"`` when nothing ran.

    Examples
    --------
    >>> ratio(3, 12), ratio(0, 0)
    ('3/12', '-')
    """
    return f"{int(failed)}/{int(calls)}" if calls else "-"


def percent(part: float, whole: float) -> str:
    """``part / whole`` as a percentage with no false precision; ``"-"`` when ``whole`` is 0.

    Examples
    --------
    >>> percent(1, 3), percent(0, 5), percent(1, 0), percent(1, 400)
    ('33%', '0%', '-', '0.2%')
    """
    if not whole:
        return "-"
    share = 100.0 * part / whole
    return f"{share:.1f}%" if 0 < share < 1 else f"{share:.0f}%"


def judged_mask(df: pd.DataFrame) -> pd.Series:
    """Rows where the algorithm itself was judged: its own verdict (stage algorithm), or a correct hull of
    the projected points that the sphere method then lost (stage preprocess, ``sphere_method`` fail).

    Rows where preprocessing raised or declined before the call, and internal errors of the checker,
    say nothing about the algorithm and are no calls of it.

    Examples
    --------
    >>> t = pd.DataFrame({"status": ["fail", "fail", "error", "error"],
    ...                   "stage": ["algorithm", "preprocess", "preprocess", "check"],
    ...                   "sphere_method": ["", "fail", "error", ""]})
    >>> judged_mask(t).tolist()
    [True, True, False, False]
    """
    stage = stages(df)
    method = (df["sphere_method"].astype("string").fillna("") if "sphere_method" in df
              else pd.Series("", index=df.index))
    return ((stage == Stage.ALGORITHM.value) | ((stage == Stage.PREPROCESS.value) & (method == "fail"))).astype(bool)


def failure_counts_by(df: pd.DataFrame, keys: list[str]) -> pd.DataFrame:
    """Per group of ``keys`` (sorted): ``failed``, the algorithm's own failures; ``calls``, rows where the
    algorithm was judged (:func:`judged_mask`); ``unjudged``, the other rows; ``method_failed``, failures
    of the sphere method or eps set-up (stage preprocess); ``internal``, internal errors (stage check).

    End to end (did the config give the input's hull?), a group failed in ``failed + method_failed`` of
    its ``calls + unjudged - internal`` rows.

    Examples
    --------
    >>> t = pd.DataFrame({"algorithm": ["a", "a", "b", "b"], "status": ["fail", "pass", "error", "fail"],
    ...                   "stage": ["algorithm", "algorithm", "preprocess", "preprocess"],
    ...                   "sphere_method": ["", "", "error", "fail"]})
    >>> failure_counts_by(t, ["algorithm"]).values.tolist()
    [['a', 1, 2, 0, 0, 0], ['b', 0, 1, 1, 2, 0]]
    """
    columns = ["failed", "calls", "unjudged", "method_failed", "internal"]
    if not len(df):
        return pd.DataFrame(columns=[*keys, *columns])
    work = df[keys].copy()
    work["failed"] = failed_mask(df, Stage.ALGORITHM).astype(int)
    work["calls"] = judged_mask(df).astype(int)
    work["unjudged"] = 1 - work["calls"]
    work["method_failed"] = failed_mask(df, Stage.PREPROCESS).astype(int)
    work["internal"] = (stages(df) == Stage.CHECK.value).astype(int)
    out = work.groupby(keys, observed=True, dropna=False)[columns].sum()
    return out.reset_index()


def failure_reasons(df: pd.DataFrame, stage: Stage = Stage.ALGORITHM, top: int = 3) -> str:
    """The commonest kinds of failure of ``stage`` in ``df``: failed checks, error types, timeouts, crashes.

    A ``fail`` row counts under its failed checks (``containment+manifoldness``),
    or ``no faces`` when it returned none, or ``output contract`` when its output
    broke the contract; an ``error`` under its exception type.

    Examples
    --------
    >>> t = pd.DataFrame({"status": ["fail", "fail", "error", "pass"], "stage": "algorithm",
    ...                   "failed_checks": ["containment", "containment", "", ""], "n_faces": [4, 5, None, 4],
    ...                   "reason": ["", "", "ValueError: x", ""]})
    >>> failure_reasons(t)
    'containment 2, ValueError 1'
    """
    failed = df[failed_mask(df, stage)]
    if not len(failed):
        return ""
    kinds = failed.apply(_failure_kind, axis=1).value_counts()
    kinds = kinds.sort_index().sort_values(ascending=False, kind="stable")
    return ", ".join(f"{kind} {count}" for kind, count in kinds.head(top).items())


def _failure_kind(row: pd.Series) -> str:
    status = row["status"]
    reason = str(row.get("reason", "") or "")
    if status == Status.ERROR:
        return reason.split(":", 1)[0] or "error"
    if status != Status.FAIL:
        return str(status)
    if reason.startswith(CONTRACT_REASON):
        return "output contract"
    n_faces = row.get("n_faces")
    if n_faces is not None and not pd.isna(n_faces) and int(n_faces) == 0:
        return "no faces"
    return str(row.get("failed_checks", "") or "").replace(",", "+") or "fail"


def claim_families(families: Sequence[str]) -> list[str]:
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
