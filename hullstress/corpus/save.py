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
        sig = rec.signature
        group = getattr(rec, "group", None)
        original = by_id.get(group.smallest_case_id) if group is not None else None
        points = np.asarray(rec.case.points, dtype=np.float64)
        dim = original.dim if original is not None else (points.shape[1] if points.ndim == 2 else 3)
        case = Case(
            points=points, dim=dim, family=rec.families[0][0],
            params=original.params if original is not None else {},
            seed=original.seed if original is not None else None,
            size=original.size if original is not None else None,
            source=f"minimised from {original.case_id}" if original is not None else "minimised",
        )
        prov = provenance_for(
            case, found_by=found_by, original_size=rec.shrink.original_size,
            extra={"signature": sig.slug, "original_case_id": original.case_id if original is not None else None},
        )
        items.append((case, prov))
    if not items:
        return []
    return add_to_corpus(directory, items, workers=workers, timeout=timeout)
