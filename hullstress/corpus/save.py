"""``run --save-corpus DIR``: every failure group the corpus does not hold yet becomes an entry.

One entry per failure group (:class:`~hullstress.triage.signature.Signature`,
the one identity of "the same failure"): its minimal case from triage, or the
group's smallest failing case when triage kept no record of it (beyond the
cap on failure folders).  A group the corpus holds as failing is not saved
again; a group it recorded as fixed that fails again replaces its entry (the
change shows in review).  Each entry records the verdict of every algorithm
config on its points (see :func:`hullstress.corpus.replay.add_to_corpus`), so
replay notices when any of them changes.
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ..case import Case
from ..options import DEFAULTS
from ..triage.signature import Signature
from .replay import add_to_corpus
from .store import held_groups, provenance_for

__all__ = ["select_for_corpus", "minimised_entry", "save_new_groups"]


def select_for_corpus(groups: Sequence[Any], held: Mapping[Signature, Any] | set[Signature]) -> list[Any]:
    """The failure groups of a run that ``held`` (the corpus's failing groups) lacks, in the run's order.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> a, b = Signature("a", "off", "n/a", status="crash"), Signature("b", "off", "n/a", status="crash")
    >>> [g.signature.algorithm for g in select_for_corpus([SimpleNamespace(signature=a), SimpleNamespace(signature=b)], {a})]
    ['b']
    """
    return [g for g in groups if g.signature not in held]


def minimised_entry(
    points: np.ndarray,
    dim: int,
    family: str,
    *,
    signature: str | None,
    found_by: str,
    original_size: int | None,
    original_case_id: str | None,
    params: dict | None = None,
    seed: int | None = None,
    size: int | None = None,
) -> tuple[Case, dict]:
    """A minimised failure as a corpus entry: the case, with the original's provenance, and its provenance record.

    Parameters
    ----------
    points : ndarray of shape (n, dim)
        The minimal case.
    dim : int
    family : str
        The generator family it was found in.
    signature : str or None
        The failure's signature slug.
    found_by : str
        The command that found it (``hullstress run ...``, ``hullstress reproduce ...``).
    original_size : int or None
        Points of the case it was minimised from.
    original_case_id : str or None
        That case's id (None when unknown).
    params, seed, size
        The original case's generator parameters, seed and size.
    """
    case = Case(
        points=np.asarray(points, dtype=np.float64), dim=dim, family=family, params=dict(params or {}),
        seed=seed, size=size,
        source=f"minimised from {original_case_id}" if original_case_id is not None else "minimised",
    )
    provenance = provenance_for(case, found_by=found_by, original_size=original_size,
                                extra={"signature": signature, "original_case_id": original_case_id})
    return case, provenance


def save_new_groups(
    directory: str | os.PathLike[str],
    groups: Sequence[Any],
    records: Sequence[Any],
    cases: Sequence[Case],
    *,
    workers: int = 0,
    timeout: float = DEFAULTS.call_timeout,
    found_by: str = "hullstress run",
) -> list[tuple[Path, bool, Signature]]:
    """Add one entry per failure group of ``groups`` that the corpus in ``directory`` does not hold.

    Parameters
    ----------
    directory : path
        The corpus folder (created when missing).
    groups : sequence of FailureGroup
        Every failure group of the run (:func:`hullstress.triage.group_failures`).
    records : sequence of TriageRecord
        Triage's records: a group with one is saved as its minimal case.
    cases : sequence of Case
        The run's cases (a group without a record is saved as its smallest failing case).

    Returns
    -------
    list of (path, written, group)
        ``written`` is False when the entry was there already.
    """
    held = held_groups(directory)
    minimal = {rec.signature: rec for rec in records}
    by_id = {c.case_id: c for c in cases}
    items: list[tuple[Case, dict, Signature]] = []
    for group in select_for_corpus(groups, held):
        original = by_id.get(group.smallest_case_id)
        rec = minimal.get(group.signature)
        if rec is None and original is None:
            continue  # no points for it at all (cannot happen for a sweep's own groups)
        points = np.asarray(rec.case.points if rec is not None else original.points, dtype=np.float64)  # type: ignore[union-attr]
        dim = original.dim if original is not None else (points.shape[1] if points.ndim == 2 else 3)
        family = group.families[0][0] if group.families else (original.family if original is not None else "corpus")
        case, provenance = minimised_entry(
            points, dim, family, signature=group.signature.slug, found_by=found_by,
            original_size=original.n_points if original is not None else None,
            original_case_id=original.case_id if original is not None else None,
            params=original.params if original is not None else None,
            seed=original.seed if original is not None else None,
            size=original.size if original is not None else None)
        if rec is None or not rec.shrink.reproduced:
            provenance["minimised"] = False
        items.append((case, provenance, group.signature))
    if not items:
        return []
    saved = add_to_corpus(directory, items, workers=workers, timeout=timeout, overwrite=True)
    return [(path, written, sig) for (path, written), (_, _, sig) in zip(saved, items)]
