"""Findings: the claims checked against one run's results table, in one place.

``python -m hullstress findings RUN`` and the report stage of ``run`` both
call :func:`compute_findings` and write its output with
:func:`write_findings` (``findings.md``, ``findings.csv``); ``summary.md`` and
``report.html`` render the same :class:`Findings`.  The claims, each split by
dimension, placement (scale and offset) and size, with the measured cause:

1. **the sphere method** (:mod:`.claim_sphere`): how often Kenwright's
   projection loses the input's hull, per dimension, with vertex loss and
   face-structure change counted apart;
2. **eps policies** (:mod:`.claim_eps`): scaled vs fixed tolerance across
   scales x1 to x1e12, offsets and the extremes, per algorithm taking eps;
3. **uniform clouds** (:mod:`.claim_control`): the control family's failures
   by variant and size;
4. **degenerate vs control** (:mod:`.claim_control`): per algorithm and
   dimension, failures on the degenerate families against uniform clouds.

A finding about a variant never charges the algorithm it wraps: the sphere
method's failures are stage ``preprocess``, every algorithm rate counts stage
``algorithm`` only.  No claim invents data: a claim whose rows are absent
says it is untested.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pandas as pd

from ..files import atomic_write_text
from .claim import Claim, claim_markdown
from .claim_control import degenerate_claim, uniform_claim
from .claim_eps import eps_claim
from .claim_sphere import sphere_claim
from .slices import sliced

__all__ = ["Findings", "compute_findings", "findings_markdown", "findings_frame", "write_findings", "run_source",
           "FINDINGS_MD", "FINDINGS_CSV"]

#: File names in the run folder (or ``findings --out``).
FINDINGS_MD = "findings.md"
FINDINGS_CSV = "findings.csv"


@dataclass(frozen=True)
class Findings:
    """The claims of one results table.

    Attributes
    ----------
    claims : tuple of Claim
        In the order of the module docstring.
    calls : int
        Rows of the table.
    source : str
        Where the table came from (a run id and its command), for the heading.
    """

    claims: tuple[Claim, ...]
    calls: int
    source: str = ""

    def claim(self, key: str) -> Claim:
        """The claim named ``key`` (``sphere-method``, ``eps-policy``, ``uniform-variants``, ``degenerate-vs-control``)."""
        for c in self.claims:
            if c.key == key:
                return c
        raise KeyError(f"no claim {key!r}; claims: {', '.join(c.key for c in self.claims)}")


def compute_findings(table: pd.DataFrame, *, source: str = "") -> Findings:
    """Check every claim against a results table.

    Parameters
    ----------
    table : DataFrame
        A results table (:func:`hullstress.results.to_frame` or :func:`hullstress.results.read_frame`).
    source : str
        What the table is (a run id and command), repeated in the Markdown.

    Returns
    -------
    Findings
    """
    work = sliced(table)
    claims = (sphere_claim(work), eps_claim(work), uniform_claim(work), degenerate_claim(work))
    return Findings(claims=claims, calls=len(table), source=source)


def run_source(meta: Mapping[str, Any]) -> str:
    """One line naming a run from its ``run.json``: id, profile, seed, sizes, families, calls."""
    args = meta.get("arguments") or {}
    parts = [f"run `{meta.get('run_id', '?')}`", f"profile `{meta.get('profile')}`", f"seed {meta.get('seed')}"]
    if args.get("sizes"):
        parts.append(f"sizes {args['sizes']}")
    if args.get("generator"):
        parts.append(f"families {', '.join(args['generator'])}")
    if meta.get("calls") is not None:
        parts.append(f"{meta['calls']} calls")
    if meta.get("complete") is False:
        parts.append("INCOMPLETE")
    return ", ".join(parts)


def findings_markdown(findings: Findings, *, level: int = 2) -> str:
    """The findings as Markdown: a heading, the source, then one section per claim."""
    out = [f"{'#' * level} Findings", ""]
    if findings.source:
        out += [f"From {findings.source} ({findings.calls} rows).", ""]
    else:
        out += [f"From a results table of {findings.calls} rows.", ""]
    for claim in findings.claims:
        out.append(claim_markdown(claim, level + 1))
    return "\n".join(out).rstrip("\n") + "\n"


def findings_frame(findings: Findings) -> pd.DataFrame:
    """Every number of every claim, one row per finest split, with a ``claim`` column (``findings.csv``)."""
    parts = [c.detail.assign(claim=c.key) for c in findings.claims if len(c.detail)]
    if not parts:
        return pd.DataFrame(columns=["claim"])
    frame = pd.concat(parts, ignore_index=True, sort=False)
    return frame[["claim", *[c for c in frame.columns if c != "claim"]]]


def write_findings(folder: str | Path, findings: Findings) -> tuple[Path, Path]:
    """Write ``findings.md`` and ``findings.csv`` into ``folder``; returns their paths."""
    folder = Path(folder)
    md, csv = folder / FINDINGS_MD, folder / FINDINGS_CSV
    atomic_write_text(md, findings_markdown(findings, level=1))
    atomic_write_text(csv, findings_frame(findings).to_csv(index=False))
    return md, csv
