"""Sweep profiles: how big a sweep is.

``quick`` is the default of ``python -m hullstress run``: every family, every
variant, one small size per dimension, one seed; it finishes within a minute
on 2 cores.  ``nightly`` runs larger sizes and more seeds of every family and
is sized for about 30 minutes on 2 cores.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType

from .errors import UsageError

__all__ = ["Profile", "PROFILES", "get_profile"]


@dataclass(frozen=True)
class Profile:
    """A named sweep size.

    Attributes
    ----------
    name : str
    sizes : mapping of int to tuple of int
        Point counts per dimension (fixed-size families ignore them).
    replicates : int
        Seeds per (family, variant, dim, size).
    timeout : float
        Default per-call timeout in seconds.
    description : str
    """

    name: str
    sizes: Mapping[int, tuple[int, ...]]
    replicates: int
    timeout: float
    description: str


PROFILES: Mapping[str, Profile] = MappingProxyType(
    {
        "quick": Profile(
            name="quick",
            sizes=MappingProxyType({2: (24,), 3: (24,)}),
            replicates=1,
            timeout=10.0,
            description="every family and variant once at a small size; under a minute on 2 cores",
        ),
        "nightly": Profile(
            name="nightly",
            # Measured on 2 cores: one seed of every family at n=256 is ~100 s of sweep;
            # n=512 roughly quadruples that (naive-2d is O(n^3), Henckel's pivoting O(n h)).
            sizes=MappingProxyType({2: (16, 64, 256, 512), 3: (16, 64, 256, 512)}),
            replicates=2,
            timeout=30.0,
            description="every family and variant at four sizes up to 512 points with two seeds; "
            "about 30 minutes on 2 cores",
        ),
    }
)


def get_profile(name: str) -> Profile:
    """Return the profile ``name`` or raise UsageError listing the valid ones."""
    try:
        return PROFILES[name]
    except KeyError:
        raise UsageError(f"unknown profile {name!r}; valid profiles: {', '.join(PROFILES)}") from None
