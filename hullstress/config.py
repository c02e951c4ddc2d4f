"""Algorithm configurations: a registered algorithm plus its sphere and eps variant."""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass

from ._registry import AlgorithmSpec, get_algorithm
from .errors import UsageError

__all__ = ["AlgorithmConfig", "expand_configs", "SPHERE_CHOICES", "EPS_CHOICES", "NO_EPS"]

SPHERE_CHOICES = ("off", "on", "both")
EPS_CHOICES = ("scaled", "fixed", "both")
#: The eps column's value for algorithms that take no ``eps`` keyword.
NO_EPS = "n/a"


@dataclass(frozen=True, order=True)
class AlgorithmConfig:
    """One way of running one algorithm.

    Attributes
    ----------
    algorithm : str
        Registered algorithm name.
    sphere : {"off", "on"}
        Whether Kenwright's support mapping and sphere projection run first.
    eps : {"scaled", "fixed", "n/a"}
        The tolerance policy passed as ``eps``; ``n/a`` when the algorithm takes none.
    """

    algorithm: str
    sphere: str = "off"
    eps: str = NO_EPS

    def __post_init__(self) -> None:
        if self.sphere not in ("off", "on"):
            raise UsageError(f"sphere must be 'off' or 'on', got {self.sphere!r}")
        if self.eps not in ("scaled", "fixed", NO_EPS):
            raise UsageError(f"eps must be 'scaled', 'fixed' or {NO_EPS!r}, got {self.eps!r}")

    @property
    def variant(self) -> str:
        """``sphere=off,eps=scaled``: the variant without the algorithm's name."""
        return f"sphere={self.sphere},eps={self.eps}"

    @property
    def label(self) -> str:
        """``name[sphere=off,eps=scaled]``: unique per config, used in reports and JUnit."""
        return f"{self.algorithm}[{self.variant}]"

    @property
    def spec(self) -> AlgorithmSpec:
        return get_algorithm(self.algorithm)


def _choices(value: str, allowed: Sequence[str], option: str) -> tuple[str, ...]:
    if value not in allowed:
        raise UsageError(f"{option} must be one of {', '.join(allowed)}, got {value!r}")
    if value == "both":
        return tuple(a for a in allowed if a != "both")
    return (value,)


def expand_configs(
    specs: Iterable[AlgorithmSpec], *, sphere: str = "both", eps: str = "both"
) -> list[AlgorithmConfig]:
    """Cross algorithms with the requested variants.

    Parameters
    ----------
    specs : iterable of AlgorithmSpec
    sphere : {"off", "on", "both"}
    eps : {"scaled", "fixed", "both"}
        Applies only to algorithms that accept ``eps``; the others get ``n/a``.

    Returns
    -------
    list of AlgorithmConfig
        Sorted, without duplicates.
    """
    spheres = _choices(sphere, SPHERE_CHOICES, "--sphere")
    epses = _choices(eps, EPS_CHOICES, "--eps")
    out = set()
    for spec in specs:
        for s in spheres:
            for e in (epses if spec.takes_eps else (NO_EPS,)):
                out.add(AlgorithmConfig(spec.name, s, e))
    return sorted(out)
