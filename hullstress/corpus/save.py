"""``run --save-corpus DIR``: minimised failures of a run become regression-corpus entries.

One entry per failing (algorithm, family) pair, the smallest minimised case
among that pair's failure groups; with ``--baseline`` only pairs with a group
new against the baseline.  Each entry records the verdict signature of every
algorithm config on its points (see :func:`hullstress.corpus.replay.add_to_corpus`),
so replay notices when any of them changes.
"""

from __future__ import annotations

import os
from collections.abc import Collection, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ..case import Case
from ..options import DEFAULTS
from .replay import add_to_corpus
from .store import ABNORMAL_STATUSES, provenance_for, with_stage

__all__ = ["corpus_signature", "select_for_corpus", "save_minimised_failures"]


def corpus_signature(check: str, stage: str = "algorithm") -> str:
    """A triage signature's check as a corpus signature (``containment`` -> ``fail:containment``)."""
    return with_stage(check if check in ABNORMAL_STATUSES else f"fail:{check}", stage)


def select_for_corpus(records: Sequence[Any], new_groups: Collection[tuple[str, ...]] | None = None) -> list[Any]:
    """The smallest minimised record per (algorithm, family), optionally only among new groups.

    Parameters
    ----------
    records : sequence of TriageRecord
        From :func:`hullstress.triage.triage_failures`.
    new_groups : collection of (algorithm, sphere, eps, family, signature), optional
        Restrict to these failure groups (the ``new`` ones against a baseline).
    """
    best: dict[tuple[str, str], Any] = {}
    for rec in records:
        sig = rec.signature
        families = [f for f, _ in rec.families]
        if new_groups is not None and not any(
                (sig.algorithm, sig.sphere, sig.eps, f, corpus_signature(sig.check, sig.stage)) in new_groups for f in families):
            continue
        key = (sig.algorithm, families[0])
        if key not in best or rec.case.n_points < best[key].case.n_points:
            best[key] = rec
    return [best[k] for k in sorted(best)]


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


def save_minimised_failures(
    directory: str | os.PathLike[str],
    records: Sequence[Any],
    cases: Sequence[Case],
    *,
    new_groups: Collection[tuple[str, ...]] | None = None,
    workers: int = 0,
    timeout: float = DEFAULTS.call_timeout,
    found_by: str = "hullstress run",
) -> list[tuple[Path, bool]]:
    """Add the selected minimised failures to the corpus in ``directory``.

    Returns
    -------
    list of (path, written)
        ``written`` is False for cases the corpus already held (same content hash).
    """
    by_id = {c.case_id: c for c in cases}
    items: list[tuple[Case, dict]] = []
    for rec in select_for_corpus(records, new_groups):
        group = getattr(rec, "group", None)
        original = by_id.get(group.smallest_case_id) if group is not None else None
        points = np.asarray(rec.case.points, dtype=np.float64)
        dim = original.dim if original is not None else (points.shape[1] if points.ndim == 2 else 3)
        items.append(minimised_entry(
            points, dim, rec.families[0][0], signature=rec.signature.slug, found_by=found_by,
            original_size=rec.shrink.original_size,
            original_case_id=original.case_id if original is not None else None,
            params=original.params if original is not None else None,
            seed=original.seed if original is not None else None,
            size=original.size if original is not None else None))
    if not items:
        return []
    return add_to_corpus(directory, items, workers=workers, timeout=timeout)
