"""Grouping a results table's failing rows by :class:`~.signature.Signature`.

A group is one signature: every failing call of one config that failed the
same way, over every family.  It keeps the counts the report shows (failing
calls, cases, the config's calls as the denominator, failures per family)
and the case triage starts from: the smallest failing case.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import pandas as pd

from .signature import FAILED_STATUSES, Signature, signature_of

__all__ = ["FailureGroup", "group_failures", "groups_frame", "GROUP_COLUMNS"]


@dataclass(frozen=True)
class FailureGroup:
    """The failing rows that share one signature.

    Attributes
    ----------
    signature : Signature
    count : int
        Failing calls with this signature.
    cases : int
        Distinct cases among them.
    calls : int
        All calls of this config (the denominator of the rate).
    smallest_case_id : str
        The failing case with the fewest points (ties: first in table order).
    smallest_n_points : int
    representative_case_id : str
        The first failing case in table order.
    smallest_index : int
        Table index of the smallest case's row (the row the group is shrunk from).
    case_ids : tuple of str
        Every failing case id, in table order.
    reasons : tuple of str
        Up to three distinct reasons, for the report.
    families : tuple of (str, int)
        Failing calls per generator family, most first (ties by name).
    dim : int
        The dimension of the config's cases (0 when the table does not say).
    """

    signature: Signature
    count: int
    cases: int
    calls: int
    smallest_case_id: str
    smallest_n_points: int
    representative_case_id: str
    smallest_index: int
    case_ids: tuple[str, ...] = field(default=())
    reasons: tuple[str, ...] = field(default=())
    families: tuple[tuple[str, int], ...] = field(default=())
    dim: int = 0

    @property
    def slug(self) -> str:
        return self.signature.slug

    @property
    def family_names(self) -> tuple[str, ...]:
        """The families with a failure of this group, most failures first."""
        return tuple(name for name, _ in self.families)


#: The columns grouping reads: the signature's and the group's counts.
_READ = ("algorithm", "sphere", "eps", "stage", "status", "reason", "failed_checks", "severity", "error_frame",
         "n_points", "case_id", "generator", "dim")


def group_failures(table: pd.DataFrame) -> list[FailureGroup]:
    """Group the failing rows of a results table by :class:`Signature`.

    Parameters
    ----------
    table : DataFrame
        A results table (:data:`hullstress.results.ROW_COLUMNS`).

    Returns
    -------
    list of FailureGroup
        Most frequent first, then by signature (a stable order for reports).

    Examples
    --------
    >>> import pandas as pd
    >>> t = pd.DataFrame({"case_id": ["a", "b", "c"], "algorithm": "alg", "sphere": "off", "eps": "n/a",
    ...                   "generator": ["dup", "grid", "dup"], "status": ["error", "error", "pass"],
    ...                   "reason": "KeyError: 3", "failed_checks": "", "n_points": [9, 4, 4]})
    >>> [(g.signature.check, g.count, g.calls, g.smallest_case_id, g.families) for g in group_failures(t)]
    [('error', 2, 3, 'b', (('dup', 1), ('grid', 1)))]
    """
    if len(table) == 0:
        return []
    denominators = table.groupby(["algorithm", "sphere", "eps"], dropna=False).size()
    # Only the columns a group reads, converted once for the whole column (a quick run has thousands of
    # failing rows of some fifty columns: selecting rows group by group, or a Series per row, costs seconds).
    failing = table.loc[table["status"].isin(FAILED_STATUSES), [c for c in _READ if c in table.columns]]
    n_points = pd.to_numeric(failing["n_points"], errors="coerce").fillna(0).astype(int).tolist()
    reasons = [str(r) for r in failing["reason"].fillna("")]
    case_ids = failing["case_id"].astype(str).tolist()
    generators = failing["generator"].astype(str)
    families = [None if missing else name for name, missing in zip(generators.tolist(), generators.isna().tolist())]
    index = failing.index.tolist()
    buckets: dict[Signature, list[int]] = {}
    for position, row in enumerate(failing.to_dict("records")):
        sig = signature_of(row)
        if sig is not None:
            buckets.setdefault(sig, []).append(position)
    groups = []
    for sig, positions in buckets.items():
        # The first of the smallest, in table order.
        smallest = min(positions, key=lambda p: n_points[p])
        ids = tuple(dict.fromkeys(case_ids[p] for p in positions))
        per_family: dict[str, int] = {}
        for p in positions:
            if families[p] is not None:  # a missing family is counted nowhere, as value_counts does
                per_family[families[p]] = per_family.get(families[p], 0) + 1
        groups.append(
            FailureGroup(
                signature=sig,
                count=len(positions),
                cases=len(ids),
                calls=int(denominators.get((sig.algorithm, sig.sphere, sig.eps), len(positions))),
                smallest_case_id=case_ids[smallest],
                smallest_n_points=n_points[smallest],
                representative_case_id=ids[0],
                smallest_index=int(index[smallest]),
                case_ids=ids,
                reasons=tuple(dict.fromkeys(reasons[p] for p in positions if reasons[p]))[:3],
                families=tuple(sorted(per_family.items(), key=lambda fn: (-fn[1], fn[0]))),
                dim=int(pd.to_numeric(failing["dim"].iat[smallest], errors="coerce")) if "dim" in failing else 0,
            )
        )
    groups.sort(key=lambda g: (-g.count, g.signature.key))
    return groups


#: Columns of :func:`groups_frame`.
GROUP_COLUMNS = ("algorithm", "sphere", "eps", "stage", "status", "checks", "severity", "error", "frame",
                 "failures", "calls", "rate", "cases", "n_families", "families", "smallest_case_id",
                 "smallest_n_points", "representative_case_id", "slug")


def groups_frame(groups: list[FailureGroup]) -> pd.DataFrame:
    """The groups as a table: signature columns, counts, rate, families, smallest and representative case."""
    cols = list(GROUP_COLUMNS)
    records = [
        {**g.signature.as_dict(), "failures": g.count, "calls": g.calls,
         "rate": round(g.count / g.calls, 3) if g.calls else 0.0, "cases": g.cases,
         "n_families": len(g.families), "families": " ".join(f"{f}:{n}" for f, n in g.families),
         "smallest_case_id": g.smallest_case_id, "smallest_n_points": g.smallest_n_points,
         "representative_case_id": g.representative_case_id, "slug": g.slug}
        for g in groups
    ]
    return pd.DataFrame.from_records(records, columns=cols)
