"""One finding: a claim's reading, its measured cause, its tables, and how each is rendered."""

from __future__ import annotations

from dataclasses import dataclass, field

import pandas as pd

__all__ = ["Claim", "claim_markdown", "markdown_table"]


@dataclass(frozen=True)
class Claim:
    """One claim checked against a run's table.

    Attributes
    ----------
    key : str
        Stable name (the ``claim`` column of ``findings.csv``).
    title : str
        What is claimed, as a heading.
    scope : str
        Which rows the numbers count (families, variants, stage, sphere), in one sentence.
    reading : tuple of str
        The numbers, as sentences.
    why : tuple of str
        The measured cause, as sentences.
    tables : tuple of (str, DataFrame)
        Compact tables for Markdown and HTML, each with a caption.
    detail : DataFrame
        Every number at the finest split (dimension, family, variant, placement, size, ...), for the CSV.
    """

    key: str
    title: str
    scope: str
    reading: tuple[str, ...]
    why: tuple[str, ...]
    tables: tuple[tuple[str, pd.DataFrame], ...] = ()
    detail: pd.DataFrame = field(default_factory=pd.DataFrame)


def markdown_table(df: pd.DataFrame) -> str:
    """A pipe table (no ``tabulate`` dependency); ``_(none)_`` for an empty frame.

    Examples
    --------
    >>> print(markdown_table(pd.DataFrame({"a": [1], "b": ["x|y"]})), end="")
    | a | b |
    |---|---|
    | 1 | x\\|y |
    """
    if df.empty:
        return "_(none)_\n"
    cols = [str(c) for c in df.columns]
    lines = ["| " + " | ".join(cols) + " |", "|" + "|".join("---" for _ in cols) + "|"]
    for rec in df.itertuples(index=False):
        cells = ("" if pd.isna(v) else str(v).replace("|", "\\|") for v in rec)
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def claim_markdown(claim: Claim, level: int = 3) -> str:
    """The claim as a Markdown section: heading, scope, reading, why, tables."""
    out = [f"{'#' * level} {claim.title}", "", f"_Scope:_ {claim.scope}", ""]
    out += [f"- {line}" for line in claim.reading]
    if claim.why:
        out += [f"- **Why:** {line}" for line in claim.why]
    for caption, table in claim.tables:
        out += ["", f"{caption}:", "", markdown_table(table).rstrip("\n")]
    return "\n".join(out) + "\n"
