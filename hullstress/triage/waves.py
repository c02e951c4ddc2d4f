"""Which failure groups shrink together, and which known minimal cases a group tries first.

Groups of one *kind* of failure (dimension, stage, status, failed checks and
severity, exception type: the signature without the config) form a chain of
waves of 1, 1, 2, 4, 8 ... groups (:func:`plan_chains`); a wave starts when
the one before it in its chain has finished, so that its groups can first try
the minimal cases found by then (:class:`Known`, :func:`remember`), ranked by
:func:`ranked`: for its own kind, same variant first, then for other kinds.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from .canonical import canonical_key
from .grouping import FailureGroup
from .records import ShrinkResult
from .signature import Signature

__all__ = ["TRIES", "Known", "remember", "failure_kind", "plan_chains", "ranked"]

#: Known minimal cases a group tries before shrinking its own case (one evaluation each): found for
#: groups of its own kind of failure, and for groups of other kinds.
TRIES = (2, 1)


@dataclass
class Known:
    """A minimal case found so far, and the groups it was found for (first one first)."""

    points: np.ndarray
    dim: int
    key: str
    slug: str
    signatures: list[Signature]



def remember(members: list[int], groups: list[FailureGroup], results: dict[int, ShrinkResult],
           known: list[Known]) -> None:
    """Remember minimal cases (one per input, up to exact transforms, with every group's signature)."""
    seen = {k.key: k for k in known}
    for i in members:
        res = results.get(i)
        if res is None or not res.reproduced:
            continue
        pts = np.asarray(res.case.points)
        key = canonical_key(pts)
        if key in seen:
            seen[key].signatures.append(groups[i].signature)
        else:
            seen[key] = Known(points=pts, dim=res.case.dim, key=key, slug=groups[i].slug,
                               signatures=[groups[i].signature])
            known.append(seen[key])




def failure_kind(signature: Signature) -> tuple[str, ...]:
    """How a group fails, whatever the config: groups of one kind often share a minimal case."""
    return (signature.stage, signature.status, signature.checks, signature.severity, signature.error)


def plan_chains(groups: Sequence[FailureGroup]) -> list[list[list[int]]]:
    """Positions of ``groups`` in chains of waves: one chain per kind, in waves of 1, 1, 2, 4, 8 ... groups.

    A kind is the dimension and the failure without the config (stage,
    status, checks, severity, exception type).  Within a chain, a wave starts
    when the previous one has finished, so that its groups can start from the
    minimal cases found first; the doubling keeps chains short.  Chains come
    in the order of their first group; depends on the groups alone: five
    groups of one kind and one of another make the chains [[0], [1], [2, 3],
    [4]] and [[5]].
    """
    by_kind: dict[tuple, list[int]] = {}
    for i, g in enumerate(groups):
        by_kind.setdefault((g.dim, *failure_kind(g.signature)), []).append(i)
    chains = []
    for positions in by_kind.values():
        chain, taken, size = [], 0, 1
        while taken < len(positions):
            chain.append(positions[taken:taken + size])
            taken += size
            if len(chain) >= 2:
                size *= 2
        chains.append(chain)
    return chains


def ranked(known: list[Known], group: FailureGroup, dim: int) -> list[Known]:
    """The known minimal cases worth trying for ``group``, best first (see :data:`TRIES`).

    First cases of the same dimension found for groups of the same kind:
    those of the same sphere and eps variant first, then of the same
    algorithm, then the smallest.  Then cases found only for other kinds:
    those that already stand for the most groups first (an input that breaks
    many configs tends to break more), then the same sphere variant, then
    the smallest.  Ties in the order they were found.
    """
    sig = group.signature
    kind = failure_kind(sig)

    def closeness(k: Known) -> tuple:
        return min((s.sphere != sig.sphere, s.eps != sig.eps, s.algorithm != sig.algorithm)
                   for s in k.signatures if failure_kind(s) == kind)

    same = [k for k in known if k.dim == dim and any(failure_kind(s) == kind for s in k.signatures)]
    same.sort(key=lambda k: (*closeness(k), len(k.points)))
    other = [k for k in known if k.dim == dim and all(failure_kind(s) != kind for s in k.signatures)]
    other.sort(key=lambda k: (-len(k.signatures), all(s.sphere != sig.sphere for s in k.signatures),
                              len(k.points)))
    return same[:TRIES[0]] + other[:TRIES[1]]
