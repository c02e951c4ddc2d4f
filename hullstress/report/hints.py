"""Hints for the terminal and the summary: patterns in a results table that have a simple remedy.

A hint reads the table only.  Today there is one: an algorithm whose every
checked hull is clockwise (negative signed volume, or area in 2D) almost
certainly uses the opposite orientation convention (Qhull's own 3D ``i``
output does), not a wrong hull; ``run --clockwise NAME`` accepts it by
reversing its faces before checking.
"""

from __future__ import annotations

import pandas as pd

__all__ = ["clockwise_hints", "MIN_CLOCKWISE_ROWS"]

#: Checked hulls needed before "every one is clockwise" is called consistent.
MIN_CLOCKWISE_ROWS = 2


def clockwise_hints(table: pd.DataFrame) -> list[str]:
    """One line per algorithm whose every checked hull has a negative signed volume (area in 2D).

    Parameters
    ----------
    table : DataFrame
        A results table (``algorithm``, ``dim``, ``volume`` and ``qhull_volume`` columns).

    Returns
    -------
    list of str

    Examples
    --------
    >>> t = pd.DataFrame({"algorithm": ["a", "a", "b"], "dim": [3, 3, 2], "volume": [-1.0, -2.0, 1.0],
    ...                   "qhull_volume": [1.0, 2.0, 1.0]})
    >>> clockwise_hints(t)[0].split(";")[0]
    'every hull a returned (2 checked) is clockwise: negative signed volume'
    """
    if table.empty or "volume" not in table:
        return []
    checked = table[pd.to_numeric(table["volume"], errors="coerce").notna()]
    checked = checked[pd.to_numeric(checked["qhull_volume"], errors="coerce").fillna(0) > 0]
    hints = []
    for algorithm, rows in checked.groupby("algorithm", sort=True, observed=True):
        volumes = pd.to_numeric(rows["volume"], errors="coerce")
        if len(rows) >= MIN_CLOCKWISE_ROWS and bool((volumes < 0).all()):
            measure = "area" if set(rows["dim"].astype(int)) == {2} else "volume"
            hints.append(
                f"every hull {algorithm} returned ({len(rows)} checked) is clockwise: negative signed {measure}; "
                f"if that is its convention (Qhull's 3D 'i' output is clockwise), run again with "
                f"--clockwise {algorithm}"
            )
    return hints
